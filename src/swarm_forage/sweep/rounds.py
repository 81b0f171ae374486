"""Seeds where they matter: a sweep's groups, their seed counts, and the rounds that choose them (used by
`sweep` for --precision and --group-runs, and by `paper` for --decide).

A group is every run of one setting, seeds apart; its name is the controller, N and what varies
(`crw_n16_null`, `dpo_n64_step_down0.4`). A group's seeds are always 1 ... n. A *group-runs file* gives
some groups their n, one `GROUP<TAB>RUNS` line each (`#` starts a comment); `sweep --group-runs FILE`
reads one, the groups it leaves out run --runs (or the experiment file's runs). After its tables a sweep
writes OUT/groups.tsv: each group's fields as the tables name them, its seeds, and its mean final P with
the 95 % interval of the bootstrap over seeds that the report uses for every interval (P_mean, P_low,
P_high: OUT/tables/bootstrap.csv through swarm_forage.study.intervals), matched through the records'
identity.

The rule of both --precision and --decide is `next_count`: a group with n seeds that needs more goes to
the count the normal approximation asks for, at least n + 1 and at most the cap."""
import csv
import hashlib
import math
import os

from swarm_forage.study import bootstrap, intervals

GROUPS = 'groups.tsv'
STATE = 'precision.tsv'  # OUT/precision.tsv: the seed counts the last --precision round chose
GROUP_FIELDS = ('group', 'controller', 'N', 'waveform', 'beta', 'alpha', 'noise', 'population', 'model',
                'identity', 'runs', 'P_mean', 'P_low', 'P_high')


class GroupRunsError(ValueError):
    pass


def next_count(n, wanted, cap):
    """The seeds a group with n seeds goes to when `wanted` would do: at least n + 1, at most `cap`."""
    return min(cap, max(n + 1, int(wanted)))


def half_width(mean, low, high):
    """The larger distance from the mean to an end of its interval (a bootstrap interval need not be
    symmetric); NaN when there is no interval."""
    return max(mean - low, high - mean)


def precise(n, mean, half, precision):
    """Whether a group's 95 % interval of final P is within `precision` of its mean (`half`: half_width). One
    seed gives no interval (never precise); a group whose every seed delivered nothing (mean 0, half-width 0)
    is."""
    return n >= 2 and half <= precision * mean


def normal_count(n, mean, half, precision):
    """The seeds at which the half-width would be precision x mean if it shrinks as 1/sqrt(n)."""
    if n < 2 or mean <= 0 or math.isnan(half):
        return n + 1
    return math.ceil(n * (half / (precision * mean)) ** 2 - 1e-9)


def read_group_runs(path):
    """{group: runs} of a group-runs file; GroupRunsError names the line that is wrong."""
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except OSError as err:
        raise GroupRunsError('cannot read %s: %s' % (path, err.strerror))
    out = {}
    for k, line in enumerate(lines, 1):
        words = line.split('#', 1)[0].split()
        if not words:
            continue
        if len(words) != 2 or not words[1].isdigit() or int(words[1]) < 1:
            raise GroupRunsError('%s:%d: want GROUP<TAB>RUNS (a group name and a whole number >= 1), got %r'
                                 % (path, k, line))
        if words[0] in out:
            raise GroupRunsError('%s:%d: group %s is listed twice' % (path, k, words[0]))
        out[words[0]] = int(words[1])
    return out


def write_group_runs(path, counts, comment=''):
    tmp = '%s.%d' % (path, os.getpid())
    with open(tmp, 'w') as f:
        f.write(''.join('# %s\n' % line for line in comment.splitlines()))
        f.write(''.join('%s\t%d\n' % kv for kv in sorted(counts.items())))
    os.replace(tmp, path)


def group_names(runs):
    """The groups of a sweep's runs, in plan order."""
    return list(dict.fromkeys(r['group'] for r in runs))


def record_identity(path):
    """world/run_info's identity of a record (what series.csv names its group by)."""
    import rosbag  # here: `sweep --help` must not need ROS
    with rosbag.Bag(path) as bag:
        for _, msg, _ in bag.read_messages(topics=['/world/run_info']):
            return msg.identity
    return ''


def final_intervals(out):
    """{identity: intervals.Interval} of every group's mean final P in OUT/tables/bootstrap.csv: draw 0
    and the 95 % percentile interval of the draws (no interval, with its reason, under 2 seeds)."""
    draws = bootstrap.read(out, key=bootstrap.by_identity)
    return {g: intervals.point_interval(draws, g, 'P', count=True) for g in draws.groups()}


def write_groups(out, runs):
    """OUT/groups.tsv from the plan `runs`, OUT/tables/series.csv (each group's condition) and
    OUT/tables/bootstrap.csv (its seeds, mean final P and interval); returns the rows. A group run_tables left
    out has empty P fields."""
    last = {}
    with open(os.path.join(out, 'tables', 'series.csv')) as f:
        for r in csv.DictReader(f):
            if r['identity'] not in last or int(r['sample']) > int(last[r['identity']]['sample']):
                last[r['identity']] = r
    finals = final_intervals(out)
    rows, first = [], {}
    for r in runs:
        first.setdefault(r['group'], r)
    number = lambda v: '' if math.isnan(v) else repr(v)  # noqa: E731
    for name, r in first.items():
        identity = record_identity(os.path.join(out, 'runs', r['key'] + '.bag'))
        s, p = last.get(identity, {}), finals.get(identity)
        rows.append({'group': name, 'controller': r['controller'], 'N': r['n'], 'waveform': s.get('waveform', ''),
                     'beta': s.get('beta', ''), 'alpha': s.get('alpha', ''), 'noise': r['noise'],
                     'population': r['population'], 'model': r['model'], 'identity': identity,
                     'runs': p.seeds if p else '', 'P_mean': number(p.estimate) if p else '',
                     'P_low': number(p.lo) if p else '', 'P_high': number(p.hi) if p else ''})
    tmp = os.path.join(out, GROUPS + '.%d' % os.getpid())
    with open(tmp, 'w') as f:
        w = csv.DictWriter(f, GROUP_FIELDS, delimiter='\t', lineterminator='\n')
        w.writeheader()
        w.writerows(rows)
    os.replace(tmp, os.path.join(out, GROUPS))
    return rows


def read_groups(out):
    """The rows of OUT/groups.tsv (as written by the sweep's last call), or [] when there is none."""
    try:
        with open(os.path.join(out, GROUPS)) as f:
            return list(csv.DictReader(f, delimiter='\t'))
    except OSError:
        return []


# --precision

def plan_digest(runs):
    """What a precision state belongs to: the record keys of every group's seed 1 (they hash every input)."""
    return hashlib.sha1(''.join(sorted(r['key'] for r in runs if r['seed'] == 1)).encode()).hexdigest()[:12]


def state_header(precision, start, cap, digest):
    return 'precision %g start %d cap %d plan %s' % (precision, start, cap, digest)


def read_state(out, header):
    """(round, {group: runs}) the last call with the same precision, start, cap and plan chose, or None."""
    path = os.path.join(out, STATE)
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except OSError:
        return None
    if len(lines) < 2 or lines[0] != '# ' + header or not lines[1].startswith('# round '):
        return None
    try:
        return int(lines[1][8:]), read_group_runs(path)
    except (ValueError, GroupRunsError):
        return None


def write_state(out, header, round_no, counts):
    write_group_runs(os.path.join(out, STATE), counts, '%s\nround %d' % (header, round_no))


def judge(rows, precision, cap):
    """Each group of groups.tsv judged after a round by its bootstrap interval: {group: (status, n, mean, half,
    next)} with status 'precise', 'capped' or 'more' (half: half_width; next: its seeds in the next round,
    else None)."""
    out = {}
    for r in rows:
        n, mean = int(r['runs']), float(r['P_mean'])
        half = half_width(mean, float(r['P_low'] or 'nan'), float(r['P_high'] or 'nan'))
        if precise(n, mean, half, precision):
            out[r['group']] = ('precise', n, mean, half, None)
        elif n >= cap:
            out[r['group']] = ('capped', n, mean, half, None)
        else:
            out[r['group']] = ('more', n, mean, half, next_count(n, normal_count(n, mean, half, precision), cap))
    return out


def describe(name, verdict, precision):
    status, n, mean, half, nxt = verdict
    rel = 'no interval' if math.isnan(half) else ('%.1f %% of the mean' % (100 * half / mean)) if mean > 0 else \
        ('every seed 0' if half == 0 else 'mean 0')
    what = {'precise': 'precise (within %g %%)' % (100 * precision),
            'capped': 'capped: not within %g %% at the cap' % (100 * precision),
            'more': 'not within %g %%: %d seeds next' % (100 * precision, nxt or 0)}[status]
    return '%s: %d seeds, final P %.4g, 95 %% bootstrap interval within %.3g of it (%s): %s' % (
        name, n, mean, half, rel, what)


# paper --decide

def _beta_equal(a, b):
    try:
        return abs(float(a) - float(b)) < 1e-9
    except (TypeError, ValueError):
        return str(a) == str(b)


def match_group(group, listings):
    """(folder, row of groups.tsv) of one group of the report's --json, [sweep_folder, arena, controller, N,
    waveform, beta]; ValueError when the sweep has no such group (or several)."""
    folder, arena, controller, n, waveform, beta = group
    rows = listings.get(os.path.realpath(folder))
    if rows is None:
        raise ValueError('the report names sweep %s, which this study did not run' % folder)
    found = [r for r in rows if r['controller'] == controller and int(r['N']) == int(n) and
             r['waveform'] == str(waveform) and (waveform == 'null' or _beta_equal(r['beta'], beta)) and
             not r['noise'] and not r['population']]
    if len(found) != 1:
        raise ValueError('the report names group %s %s N=%s %s beta %s, which sweep %s has %s' % (
            arena, controller, n, waveform, beta, folder, 'not' if not found else '%d times' % len(found)))
    return os.path.realpath(folder), found[0]


def decide(claims, listings, caps):
    """The seeds `paper --decide` asks for next: `claims` is paper_report.py's --json list, `listings` maps
    each sweep folder (realpath) to its groups.tsv rows, `caps` each folder to its cap. Every undecided
    claim's groups below their cap go to seeds_needed, the number the report prints (claims.normal_seeds; null:
    twice their seeds), by next_count: at least one more, at most the cap. Returns
    ({folder: {group: runs}} of the groups to raise, [one line per undecided claim])."""
    raises, lines = {}, []
    for c in claims:
        if c.get('verdict') != 'undecided':
            continue
        want, raised, capped = c.get('seeds_needed'), [], []
        for folder, row in (match_group(g, listings) for g in c.get('groups', [])):
            n, cap = int(row['runs']), caps[folder]
            if n >= cap:
                capped.append(row['group'])
                continue
            target = next_count(n, want if want else 2 * n, cap)
            mine = raises.setdefault(folder, {})
            mine[row['group']] = max(target, mine.get(row['group'], 0))
            raised.append('%s %d -> %d' % (row['group'], n, target))
        num = lambda v: '%.3g' % v if isinstance(v, (int, float)) else str(v)  # noqa: E731
        lines.append('(%s) undecided (margin %s, interval [%s, %s], %s): %s' % (
            c.get('claim'), num(c.get('margin')), num(c.get('low')), num(c.get('high')),
            'the report\'s seeds to decide it: %s' % want if want else 'no estimate of the seeds: twice them',
            ('raising ' + ', '.join(raised)) if raised else 'every group at its cap (%s)' % ', '.join(capped)))
    return raises, lines


def precision_rounds(name, out, every, precision, start, cap, sweep_once, dry_run, prog):
    """sweep --precision: round after round, `sweep_once(counts)` (0 when its records and tables are whole)
    then `judge`, until every group is precise or capped. `every` is the plan at the cap (to name the
    groups and the state). Returns the exit status."""
    header = state_header(precision, start, cap, plan_digest(every))
    state = read_state(out, header)
    number, counts = state if state else (1, {g: start for g in group_names(every)})
    while True:
        seeds = sorted(set(counts.values()))
        print('%s: round %d%s: %d groups, %s seeds each (cap %d, precision %g)' % (
            prog, number, ' (resumed: the seeds the last call chose)' if state and number == state[0] else '',
            len(counts), seeds[0] if len(seeds) == 1 else '%d-%d' % (seeds[0], seeds[-1]), cap, precision), flush=True)
        if not dry_run:
            write_state(out, header, number, counts)
        code = sweep_once(counts)
        if code or dry_run:
            if dry_run:
                print('%s: dry run: later rounds depend on this one\'s results (at most %d seeds per group)'
                      % (prog, cap))
            return code
        rows = read_groups(out)
        missing = [r['group'] for r in rows if not r['runs']]
        if missing:
            print('%s: problem: %d groups have no row in %s (e.g. %s): their precision cannot be judged' % (
                prog, len(missing), os.path.join(out, 'tables', 'series.csv'), missing[0]), flush=True)
            return 1
        verdicts = judge(rows, precision, cap)
        more = {g: v[4] for g, v in verdicts.items() if v[0] == 'more'}
        for g, v in verdicts.items():
            if not more or v[0] == 'more':
                print('%s: %s' % (prog, describe(g, v, precision)))
        if not more:
            print('%s: %s: every group precise or capped after round %d: %d precise, %d capped' % (
                prog, name, number, sum(v[0] == 'precise' for v in verdicts.values()),
                sum(v[0] == 'capped' for v in verdicts.values())), flush=True)
            return 0
        counts.update(more)
        number += 1
