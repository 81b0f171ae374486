"""The ablation of FORDYCA 2019's quirks (docs/FIDELITY.md, "The ablation: which quirks matter"), made from its
sweeps' tables (ablation_table; `paper --ablation` sweeps and then runs it).

The ablation is experiment files run through `sweep` (config/experiments/ablation_*.yaml, ARMS), each one
controller, arena and N with the model as an axis (experiment file key `models`): a *row* is a quirk set,
named by models.model_name of the quirks its records carry (`swarm_forage`, `fordyca_2019`,
`swarm_forage+transport_wander`, `fordyca_2019+dynamics2d_contacts`), whichever model is the default; an
*arm* is a (sweep folder, controller, N). Per arm and row: the mean final P with the 95 % interval of the
bootstrap over seeds (the sweep's tables/bootstrap.csv through swarm_forage.study.intervals, as every point
and claim of the report), min-max over seeds (each record's final world/performance, whose mean must be the
tables'), and the robots stalled at T (the last swarm/status of each record: robots that have not moved 1 cm
in the last 50 ticks), mean and min-max. Per
row, claim (d) as the report decides it (paper_claims.claim_d over the same bootstrap): q = |P(DPO 2,048) -
P(CRW 8,192)| / P(CRW 8,192) in 96x48 with its interval and verdict, where the row has both arms.
"""
import csv
import glob
import math
import os

from swarm_forage.experiment import kinds, models
from swarm_forage.study import bootstrap, claims, intervals, paper_claims

# The ablation's experiment files, one arm each: DPO's jam in 64x32 and 96x48 and CRW's crowd of claim (d).
ARMS = ('ablation_dpo_64x32', 'ablation_dpo_96x48', 'ablation_crw_96x48')
CSV_FIELDS = ('arm', 'row', 'seed', 'model_version', 'quirks', 'identity', 'ticks', 'final_P', 'stalled', 'code',
              'record')


class AblationError(Exception):
    pass


def record_facts(path):
    """What the table needs of one record: run_info's controller, arena, N, seed, ticks, identity and quirks
    (its world and controller constants' quirks= words), the provenance's model version and code, its final P
    (the last world/performance) and the robots stalled at its last tick (the sum over that tick's
    swarm/status ranges)."""
    import rosbag  # here: the module's pure parts need no ROS
    import rospy
    with rosbag.Bag(path) as bag:
        info = next((m for _, m, _ in bag.read_messages(topics=['/world/run_info'])), None)
        prov = next((m for _, m, _ in bag.read_messages(topics=['/world/provenance'])), None)
        if info is None or prov is None:
            raise AblationError('%s: no world/run_info or world/provenance (not a sweep\'s record)' % path)
        end = bag.get_end_time()
        last, stalled, final, final_tick = -1, 0, None, -1
        # Both topics are stamped at their tick's simulated time: the last seconds hold the last tick.
        for start in (rospy.Time.from_sec(max(0.0, end - 2.0)), None):
            for topic, m, _ in bag.read_messages(topics=['/swarm/status', '/world/performance'], start_time=start):
                if topic == '/world/performance':
                    if m.tick > final_tick:
                        final, final_tick = float(m.cumulative), m.tick
                    continue
                if m.tick > last:
                    last, stalled = m.tick, 0
                if m.tick == last:
                    stalled += m.stalled
            if last >= 0 and final is not None:
                break
    quirks = set()
    for word in (info.world_constants + ' ' + info.controller_constants).split():
        if word.startswith('quirks='):
            quirks.update(q for q in word[len('quirks='):].split(',') if q)
    return {'controller': info.controller, 'arena': info.arena, 'N': info.swarm_size, 'seed': info.seed,
            'ticks': info.ticks, 'identity': info.identity, 'quirks': quirks, 'row': models.model_name(quirks),
            'model_version': prov.model_version, 'code': prov.code, 'stalled': stalled if last >= 0 else None,
            'final_P': final, 'record': os.path.basename(path)}


def planned_rows(folder):
    """{(controller, N): {row}} of the runs the sweep of `folder` planned (OUT/runs.tsv, written by its last call):
    so that a cell not run yet shows as such."""
    out = {}
    try:
        with open(os.path.join(folder, 'runs.tsv')) as f:
            lines = [line.rstrip('\n').split('\t') for line in f if line.strip()]
    except OSError:
        return out
    default = models.models()['default']
    for words in lines:
        w = dict(x.split(':=', 1) for x in words[1:] if ':=' in x)
        quirks = models.model_quirks(w.get('model', default)) | {q for q in w.get('quirks', '').split(',') if q}
        out.setdefault((w.get('controller'), int(w.get('n_robots', 0))), set()).add(models.model_name(quirks))
    return out


def in_order(quirks, order):
    """The quirks in the listing's order (unknown ones last, by name)."""
    return [q for q in order if q in quirks] + sorted(set(quirks) - set(order))


def row_order(name):
    """swarm_forage and fordyca_2019 first, then each model's single quirks in the listing's order."""
    order = [q['name'] for q in models.models()['quirks']]
    parts = name.split('+')
    return (len(parts) > 1, parts[0] != 'swarm_forage',
            [order.index(q) if q in order else len(order) for q in parts[1:]], name)


class Arm:
    """One column pair of the table: a sweep folder's groups of one controller and N."""

    def __init__(self, folder, controller, n, arena):
        self.folder, self.controller, self.n, self.arena = folder, controller, n, arena
        self.records = {}  # row -> [facts]
        self.draws = None
        self.missing = None  # why there is no bootstrap

    @property
    def name(self):
        return '%s_%s_n%d' % (os.path.basename(os.path.normpath(self.folder)), self.controller, self.n)

    def title(self):
        label = kinds.display_name(self.controller)
        return '%s %s N=%s' % (label, (self.arena or '?').replace('x', '×'), '{:,}'.format(self.n))


def collect(folders):
    """[Arm] of the sweep folders, each with its planned records by row and its bootstrap by identity."""
    arms = {}
    for folder in folders:
        if not os.path.isdir(folder):
            raise AblationError('%s is not a sweep folder (no such folder)' % folder)
        paths = sorted(glob.glob(os.path.join(folder, 'plan', '*.bag')))
        for path in paths:
            if not os.path.isfile(path):  # a link to a record no longer there: the sweep has not finished
                continue
            facts = record_facts(path)
            key = (folder, facts['controller'], facts['N'])
            arm = arms.setdefault(key, Arm(folder, facts['controller'], facts['N'], facts['arena']))
            arm.records.setdefault(facts['row'], []).append(facts)
        for (controller, n), rows in planned_rows(folder).items():
            arm = arms.setdefault((folder, controller, n), Arm(folder, controller, n, None))
            for row in rows:
                arm.records.setdefault(row, [])
        try:
            draws = bootstrap.read(folder, key=bootstrap.by_identity)
            missing = None
        except bootstrap.BootstrapMissing as err:
            draws, missing = None, str(err)
        for (f, _, _), arm in arms.items():
            if f == folder:
                arm.draws, arm.missing = draws, missing
    return [arms[k] for k in sorted(arms, key=lambda k: (folders.index(k[0]), k[1], k[2]))]


def _cell(arm, row, most):
    """The arm's two cells of a row: final P and stalled at T."""
    runs = sorted((f for f in arm.records.get(row, []) if f['final_P'] is not None), key=lambda f: f['seed'])
    if not runs:
        return 'not run', 'not run'
    identities = {f['identity'] for f in runs}
    if len(identities) != 1:
        raise AblationError('%s: row %s has records of %d identities (%s): one group per row and arm'
                            % (arm.folder, row, len(identities), ', '.join(sorted(identities))))
    p = [f['final_P'] for f in runs]
    mean = sum(p) / len(p)
    point = intervals.point_interval(arm.draws, runs[0]['identity'], 'P', None, len(p), count=True)
    if arm.draws is not None and (math.isnan(point.estimate) or abs(point.estimate - mean) > 1e-6 * max(1.0, mean)):
        raise AblationError('%s: row %s: the records\' mean final P %.6g is not the tables\' %.6g (seeds %s): '
                            'tables of other records; run the sweep again to remake them'
                            % (arm.folder, row, mean, point.estimate, ','.join(str(f['seed']) for f in runs)))
    if arm.draws is None:
        point = intervals.point_interval(None, runs[0]['identity'], 'P', mean, len(p), count=True)
    text = '%.1f [%.1f, %.1f]' % (point.estimate, point.lo, point.hi) if point.drawn else \
        '%.1f (%s)' % (point.estimate, point.note)
    text += ' (%.0f–%.0f)' % (min(p), max(p))
    if len(p) < most:
        text += ', %d seeds' % len(p)
    stalled = [f['stalled'] for f in runs if f['stalled'] is not None]
    st = '%.1f (%d–%d)' % (sum(stalled) / len(stalled), min(stalled), max(stalled)) if stalled else '—'
    return text, st


def claim_d(arms, row, sizes=None):
    """claims.Claim (d) of a row: paper_claims.claim_d on the bootstrap of the row's groups in the arms
    (`sizes`: (arena, N of DPO, N of CRW), the paper's by default)."""
    identities = {}
    for arm in arms:
        runs = arm.records.get(row, [])
        if runs and arm.draws is not None:
            identities.setdefault(arm.folder, set()).add(runs[0]['identity'])
    draws = {f: bootstrap.read(f, identities=ids) for f, ids in identities.items()}
    return paper_claims.claim_d(draws, kinds.display_name,
                                *(sizes or ()))[0]


def make(folders, sizes=None):
    """(markdown lines, csv rows, {row: claims.Claim (d)}) of the ablation of the sweep folders; `sizes`: claim
    (d)'s (arena, N of DPO, N of CRW), the paper's (96x48, 2,048, 8,192) by default."""
    arena_d, dpo_n, crw_n = sizes or paper_claims.D_SIZES
    arms = collect(folders)
    if not arms:
        raise AblationError('no planned record and no plan in %s (run the sweeps first: paper --ablation)'
                            % ', '.join(folders))
    rows = sorted({r for a in arms for r in a.records}, key=row_order)
    most = max((len(fs) for a in arms for fs in a.records.values()), default=0)
    has_d = any(a.controller == 'dpo' and a.n == dpo_n for a in arms) and \
        any(a.controller == 'crw' and a.n == crw_n for a in arms)
    head, rule = '| row |', '|---|'
    for a in arms:
        head += ' %s: final P | stalled at T |' % a.title()
        rule += '---|---|'
    if has_d:
        head += ' (d) q = \\|ΔP\\| / P(CRW) | (d) |'
        rule += '---|---|'
    lines = [head, rule]
    verdicts = {}
    for row in rows:
        line = '| %s |' % row
        for a in arms:
            line += ' %s | %s |' % _cell(a, row, most)
        if has_d:
            c = claim_d(arms, row, (arena_d, dpo_n, crw_n))
            verdicts[row] = c
            if c.verdict == 'not measured':
                line += ' not run | not run |'
            else:
                line += ' %.3f [%.3f, %.3f] | %s |' % (c.estimate, c.low, c.high, c.verdict)
        lines.append(line)
    table = []
    codes, versions = {}, set()
    order = [q['name'] for q in models.models()['quirks']]
    for a in arms:
        for row in rows:
            for f in sorted(a.records.get(row, []), key=lambda f: f['seed']):
                codes[f['code']] = codes.get(f['code'], 0) + 1
                versions.add(f['model_version'])
                table.append({'arm': a.name, 'row': row, 'seed': f['seed'], 'model_version': f['model_version'],
                              'quirks': ';'.join(in_order(f['quirks'], order)) or 'none', 'identity': f['identity'],
                              'ticks': f['ticks'], 'final_P': '%.0f' % f['final_P'] if f['final_P'] is not None
                              else '', 'stalled': '' if f['stalled'] is None else f['stalled'], 'code': f['code'],
                              'record': f['record']})
    draws = next((a.draws.draws for a in arms if a.draws is not None), 0)
    ticks = sorted({f['ticks'] for a in arms for fs in a.records.values() for f in fs})
    text = [
        'Final P: mean [95 %% bootstrap interval over seeds, %s draws] (min–max over seeds); stalled: robots that '
        'have not moved 1 cm in the last 50 ticks at T, mean (min–max). %s seeds per cell unless marked; %s ticks.'
        % (draws or 'no', most, ', '.join('{:,}'.format(t) for t in ticks) or '—'), '']
    if has_d:
        text += ['(d): q = |P(DPO %s N=%s) − P(CRW %s N=%s)| / P(CRW), mean final P, with its 95 %% '
                 'bootstrap interval (each group\'s seeds resampled, q recomputed per draw); *agrees* when the whole '
                 'interval is ≤ %.2f, *disagrees* when it is wholly above, *undecided* when it straddles %.2f or a '
                 'group has fewer than %d seeds: the report\'s claim (d) (docs/decisions.md).'
                 % (arena_d.replace('x', '×'), '{:,}'.format(dpo_n), arena_d.replace('x', '×'), '{:,}'.format(crw_n),
                    claims.WITHIN, claims.WITHIN, claims.MIN_SEEDS), '']
    lacking = [a.missing for a in arms if a.missing]
    if lacking:
        text += ['No bootstrap: %s.' % '; '.join(sorted(set(lacking))), '']
    made = ', '.join('%s (%d runs)' % kv for kv in sorted(codes.items()))
    tail = ['', 'The runs were made by the code %s; model version %s.' % (
        made or '(none)', ', '.join(map(str, sorted(versions))) or '—')]
    return text + lines + tail, table, verdicts


def write(folders, output, csv_path=None, title='The ablation: which quirks matter', note='', sizes=None):
    """Writes the markdown table (and the per-run CSV); returns {row: claims.Claim (d)}."""
    lines, table, verdicts = make(folders, sizes)
    head = ['# ' + title, ''] + ([note, ''] if note else [])
    with open(output, 'w') as f:
        f.write('\n'.join(head + lines) + '\n')
    if csv_path:
        with open(csv_path, 'w') as f:
            w = csv.DictWriter(f, CSV_FIELDS, lineterminator='\n')
            w.writeheader()
            w.writerows(table)
    return verdicts

