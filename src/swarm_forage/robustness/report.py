"""The report's "Beyond the paper: robustness" section (paper_report.py --robustness; docs/robustness-study.md):
which controller degrades least under noise (SAA) and under population dynamics (PD), at each N, by a
criterion stated in the report and computed from the sweeps' robustness tables, never by hand.

Criterion, per sweep, arena, measure and N: the settings compared are those with a value for every
controller (a setting without one, e.g. an unstable queue, is named and left out); each seed's score is
its runs' mean of the measure over those settings (SAA: the DTW distance d, lower is better; PD: theta,
higher is better; the normalised forms rank the same, since sigma(-d) - sigma(d) = -tanh(d/2) falls with
d and sigma(theta) - sigma(-theta) rises with theta, but saturate at +-1 for block counts); a controller's
score is the mean over seeds with its 95 % confidence interval (t, seeds - 1 degrees of freedom). The best
mean "degrades least" when its interval does not overlap the runner-up's; otherwise no controller is
singled out. The final P against the reference (P / P_reference - 1, mean over the settings) is shown
beside it."""
import os

from swarm_forage.robustness import tables as rt

WHAT = {'saa': ('sensor and actuator noise (SAA)', 'd', 'DTW distance d to the noise-free P(t)', 'lowest'),
        'pd': ('population dynamics (PD)', 'theta', 'theta = P(T) - ((T - T_bar) / T) P_reference(T)',
               'highest')}


def setting_of(p):
    """What a point's setting is, as text (the same for every controller and N of the sweep)."""
    if p['measure'] == 'saa':
        devices = [w.split('=')[0].replace('noise/', '') for w in p['noise'].split()]
        return 'level %g (%s)' % (p['noise_level'], ', '.join(devices))
    return '%s x%g' % (rt.family_name(p['family']), p['multiplier'])


def _overlap(a, b):
    if a.ci95 != a.ci95 or b.ci95 != b.ci95:  # nan: one seed
        return True
    return a.mean - a.ci95 <= b.mean + b.ci95 and b.mean - b.ci95 <= a.mean + a.ci95


def verdicts(points, measure, label):
    """[(arena, N, rows {controller: (Spread, relative P loss)}, verdict text, winner or None, settings used,
    settings left out {setting: reason})] of one sweep's points of `measure`."""
    out = []
    pts = [p for p in points if p['measure'] == measure]
    lower_better = measure == 'saa'
    for arena, n in sorted({(p['arena'], p['N']) for p in pts}):
        here = [p for p in pts if p['arena'] == arena and p['N'] == n]
        controllers = sorted({p['controller'] for p in here})
        by = {(p['controller'], setting_of(p)): p for p in here}
        settings = sorted({setting_of(p) for p in here})
        used = [s for s in settings if all(by.get((c, s)) and by[(c, s)]['valid'] for c in controllers)]
        left_out = {}
        for s in settings:
            if s not in used:
                bad = [c for c in controllers if (c, s) in by and not by[(c, s)]['valid']]
                reasons = {by[(c, s)]['status'] for c in bad}
                if len(reasons) == 1 and len(bad) == len(controllers):  # one reason for all: said once
                    left_out[s] = 'every controller: ' + reasons.pop()
                else:
                    left_out[s] = '; '.join(sorted('%s: %s' % (label(c), by[(c, s)]['status']) for c in bad)) or \
                        'not run for every controller'
        rows = {}
        for c in controllers:
            seeds = set.intersection(*[set(by[(c, s)]['seeds']) for s in used]) if used else set()
            scores = [sum(by[(c, s)]['seeds'][k] for s in used) / len(used) for k in sorted(seeds)]
            rel = [by[(c, s)]['P'] / by[(c, s)]['P_reference'] - 1 for s in used
                   if by[(c, s)]['P_reference'] > 0]  # (nan compares false: left out too)
            rows[c] = (rt.Spread(scores), sum(rel) / len(rel) if rel else float('nan'))
        ranked = sorted((c for c in controllers if rows[c][0].n), key=lambda c: rows[c][0].mean,
                        reverse=not lower_better)
        winner = None
        if not used:
            text = 'not measured: no setting has a value for every controller'
        elif len(ranked) < 2:
            text = 'not measured: fewer than two controllers with a value'
        elif rows[ranked[0]][0].n < 2:
            text = 'cannot tell: one seed per setting (no spread); best mean %s' % label(ranked[0])
        elif _overlap(rows[ranked[0]][0], rows[ranked[1]][0]):
            text = 'no clear winner: %s and %s are within each other\'s 95 %% CI' % (label(ranked[0]),
                                                                                    label(ranked[1]))
        else:
            winner = ranked[0]
            text = '%s degrades least' % label(winner)
        out.append((arena, n, rows, text, winner, used, left_out))
    return out


def queue_lines(points, label):
    """The PD part's queue check: the settings whose runs' population records differ from the M/M/1 queue
    the measure assumes by more than 20 % (robustness.csv's queue_differs), with both values."""
    checked = [p for p in points if p['measure'] == 'pd' and p['queue']['queue_differs'] is not None]
    off = [p for p in checked if p['queue']['queue_differs']]
    if not checked:
        return []
    if not off:
        return ['Queue check: in all %d settings with population records, the measured time out of the swarm and '
                'robots out are within 20 %% of the M/M/1 queue the measure assumes.' % len(checked), '']

    def fmt(v):
        return '—' if v is None else '%.3g' % v
    lines = ['Queue check: %d of %d settings with population records differ by more than 20 %% from the M/M/1 '
             'queue the measure assumes (docs/robustness-measures.md, The queue, measured):' % (len(off), len(checked)),
             '', '| arena | N | controller | setting | time out: measured / W (ticks) | robots out: measured / L |',
             '|---|---|---|---|---|---|']
    for p in sorted(off, key=lambda p: (p['arena'], p['N'], label(p['controller']), setting_of(p))):
        q = p['queue']
        lines.append('| %s | %d | %s | %s | %s / %s | %s / %s |' % (
            p['arena'], p['N'], label(p['controller']), setting_of(p), fmt(q['time_out_measured']),
            fmt(q['time_out_queue']), fmt(q['out_measured']), fmt(q['out_queue'])))
    return lines + ['']


def section(folders, label):
    """The markdown lines of the section for the robustness sweep folders."""
    lines = ['## Beyond the paper: robustness', '',
             'Which controller degrades least under noise and under robots failing, at each N (the package\'s '
             'docs/robustness-study.md). **Criterion:** ' + __doc__.split(
                 'Criterion, ')[1].replace('\n', ' ').strip(), '']
    summary = []
    for folder in folders:
        name = os.path.basename(os.path.normpath(folder))
        points = rt.read(folder) if rt.exists(folder) else []
        if not points:
            lines += ['### %s' % name, '', 'not measured: %s has no robustness table with a value (%s)' % (
                folder, 'tables/robustness.csv missing' if not rt.exists(folder) else 'no noisy or PD group'), '']
            continue
        for measure in ('saa', 'pd'):
            found = verdicts(points, measure, label)
            if not found:
                continue
            title, short, long, best = WHAT[measure]
            lines += ['### %s: %s' % (name, title), '',
                      'Score: %s (%s is best): each seed\'s mean over the settings compared, then mean ± 95 %% CI '
                      'over the seeds; beside it the final P against the reference (mean over the settings).'
                      % (long, best), '']
            controllers = sorted({c for f in found for c in f[2]}, key=lambda c: label(c))
            lines += ['| arena | N | ' + ' | '.join(label(c) for c in controllers) + ' | verdict |',
                      '|---|---|' + '---|' * len(controllers) + '---|']
            for arena, n, rows, text, winner, used, left_out in found:
                cells = []
                for c in controllers:
                    if c not in rows or not rows[c][0].n:
                        cells.append('—')
                        continue
                    s, rel = rows[c]
                    cells.append('%s %.3g ± %.2g (%d seeds); P %+.1f %%' % (short, s.mean, s.ci95 if s.n > 1 else 0,
                                                                           s.n, 100 * rel))
                lines.append('| %s | %d | %s | %s |' % (arena, n, ' | '.join(cells), text))
                summary.append(('%s, %s, %s, N = %d' % (name, measure.upper(), arena, n), text))
            used_all = sorted({s for f in found for s in f[5]})
            lines += ['', 'Settings compared: %s.' % ', '.join(used_all)]
            dropped = {s: why for f in found for s, why in f[6].items()}
            if dropped:
                lines += ['Left out (no value for every controller): %s.' % '; '.join(
                    '%s (%s)' % kv for kv in sorted(dropped.items()))]
            lines.append('')
            if measure == 'pd':
                lines += queue_lines(points, label)
    if summary:
        lines[4:4] = ['| study, N | verdict |', '|---|---|'] + ['| %s | %s |' % s for s in summary] + ['']
    return lines, summary
