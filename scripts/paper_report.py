#!/usr/bin/env python3
"""The paper's claims against measured sweeps, claim by claim, as markdown:

    paper_report.py --ideal DIR [DIR ...] [--time-varying DIR] [--robustness DIR ...] [--figures FIGDIR] --output REPORT.md

Each verdict comes from an explicit criterion computed from the sweeps' tables (written in the report
next to the numbers it used), never by hand: agrees, disagrees, or not measured (what is missing).
--robustness adds the section "Beyond the paper: robustness" (swarm_forage.robustness_report): which
controller degrades least under noise and under population dynamics, at each N.
The model the runs used (swarm_forage or fordyca_2019, and any quirks added) is read from each record's
world/run_info (its world and controller constants: the identity words quirks=...), never from a flag.
"""
import argparse
import glob
import math
import os
import sys
from collections import defaultdict

from swarm_forage import runs
from swarm_forage import experiment
from swarm_forage import robustness_report

PAPER = ('crw', 'dpo', 'gp_dpo')  # the controllers the paper's claims are about


def label(c):
    """A controller's display name, built-in or plugin (run_experiment --controllers)."""
    return experiment.controller_kind(c)['display_name']


Z_TOLERANCE = 0.01  # "Z below 0.5": below 0.49 (Z of a swarm without interference is 0.5 +- rounding)


def finals(folder):
    """(arena, controller, N) -> (final P mean, ci95, runs) of the ideal groups."""
    return {k: (float(r['P_mean']), float(r['P_ci95']), int(r['runs']))
            for k, r in runs.final_samples(runs.sweep_table(folder, 'series')).items()}


def ideal_metric(folder, name, size_key, value_key):
    """(arena, controller) -> {N: value} of the valid ideal rows."""
    out = defaultdict(dict)
    for r in runs.sweep_table(folder, name):
        if runs.ideal(r) and r['valid'] == '1':
            out[(r['arena'], r['controller'])][int(r[size_key])] = float(r[value_key])
    return out


def spearman(xs, ys):
    def ranks(v):
        order = sorted(range(len(v)), key=lambda i: v[i])
        r = [0.0] * len(v)
        for k, i in enumerate(order):
            r[i] = k
        return r
    if len(xs) < 3:
        return float('nan')
    rx, ry = ranks(xs), ranks(ys)
    mx, my = sum(rx) / len(rx), sum(ry) / len(ry)
    num = sum((a - mx) * (b - my) for a, b in zip(rx, ry))
    den = math.sqrt(sum((a - mx) ** 2 for a in rx) * sum((b - my) ** 2 for b in ry))
    return num / den if den else float('nan')


class Report:
    def __init__(self):
        self.lines, self.verdicts = [], []

    def claim(self, label, paper, criterion, verdict, evidence):
        self.verdicts.append((label, verdict))
        self.lines += ['### (%s) %s' % (label, paper), '', '- **Criterion:** ' + criterion,
                       '- **Measured:** ' + evidence, '- **Verdict:** **%s**' % verdict, '']


def sweep_of(ideal, arena):
    """The first ideal sweep folder holding `arena`, or None."""
    return next((f for f in ideal if any(k[0] == arena for k in finals(f))), None)


def sweep_or_unmeasured(rep, ideal, arena, letter, paper, missing):
    """The ideal sweep of `arena`; without one, claim `letter` is reported not measured (None)."""
    key = sweep_of(ideal, arena)
    if key is None:
        rep.claim(letter, paper, '—', 'not measured', missing)
    return key


def claim_a(rep, ideal):
    paper = 'In 32×16, CRW is the most scalable (lowest e), and DPO/GP-DPO perform better at small N'
    key = sweep_or_unmeasured(rep, ideal, '32x16', 'a', paper, 'no 32×16 sweep')
    if key is None:
        return
    e = ideal_metric(key, 'scalability', 'N2', 'e')
    p = finals(key)
    sizes = sorted({n for (a, c, n) in p if a == '32x16'})
    top = sizes[-3:]
    mean_e = {c: sum(e[('32x16', c)].get(n, float('nan')) for n in top) / len(top) for c in PAPER}
    small = [n for n in sizes if n <= 64]
    wins = {c: sum(p.get(('32x16', c, n), (0,))[0] > p.get(('32x16', 'crw', n), (0,))[0] for n in small)
            for c in ('dpo', 'gp_dpo')}
    ok_e = all(not math.isnan(v) for v in mean_e.values()) and mean_e['crw'] < min(mean_e['dpo'], mean_e['gp_dpo'])
    ok_small = all(3 * wins[c] >= 2 * len(small) for c in wins)
    rep.claim('a', paper,
              'mean e over the three largest N (%s) is lowest for CRW; and DPO and GP-DPO each deliver more than '
              'CRW (final P) at two thirds or more of the sizes N ≤ 64' % ', '.join(map(str, top)),
              'agrees' if ok_e and ok_small else 'disagrees',
              'mean e: %s; sizes N ≤ 64 where DPO / GP-DPO beat CRW: %d / %d of %d' % (
                  ', '.join('%s %.3f' % (label(c), v) for c, v in mean_e.items()), wins['dpo'], wins['gp_dpo'],
                  len(small)))


def claim_b(rep, ideal):
    paper = 'In 64×32, for DPO and GP-DPO the N of maximum P ≈ the N of the first Z below 0.5'
    key = sweep_or_unmeasured(rep, ideal, '64x32', 'b', paper, 'no 64×32 ideal sweep')
    if key is None:
        return
    p, z = finals(key), ideal_metric(key, 'self_organization', 'm_i', 'Z_mean')
    parts, ok = [], True
    for c in ('dpo', 'gp_dpo'):
        sizes = sorted(n for (a, cc, n) in p if a == '64x32' and cc == c)
        n_max = max(sizes, key=lambda n: p[('64x32', c, n)][0])
        below = [n for n in sorted(z[('64x32', c)]) if z[('64x32', c)][n] < 0.5 - Z_TOLERANCE]
        n_z = below[0] if below else None
        close = n_z is not None and abs(math.log2(n_max) - math.log2(n_z)) <= 1
        ok = ok and close
        parts.append('%s: max P at N = %d (%.0f blocks), first Z < %.2f at %s' % (
            label(c), n_max, p[('64x32', c, n_max)][0], 0.5 - Z_TOLERANCE,
            'N = %d (Z = %.3f)' % (n_z, z[('64x32', c)][n_z]) if n_z else 'no N'))
    rep.claim('b', paper, 'the two sizes are within a factor of 2 (one step of the power-of-two sizes) for both; '
              '"below 0.5" means below %.2f' % (0.5 - Z_TOLERANCE), 'agrees' if ok else 'disagrees', '; '.join(parts))


def claim_c(rep, ideal):
    paper = 'CRW is the best performer at the largest N'
    parts, ok, seen = [], True, False
    for folder in ideal:
        p = finals(folder)
        for arena in sorted({k[0] for k in p}):
            n = max(k[2] for k in p if k[0] == arena)
            vals = {c: p.get((arena, c, n), (float('nan'),))[0] for c in PAPER}
            best = max(vals, key=lambda c: vals[c] if not math.isnan(vals[c]) else -1)
            ok = ok and best == 'crw'
            seen = True
            parts.append('%s, N = %d: %s' % (arena, n, ', '.join('%s %.0f' % (label(c), v) for c, v in vals.items())))
    rep.claim('c', paper, 'at the largest N of every ideal sweep, CRW has the highest mean final P',
              ('agrees' if ok else 'disagrees') if seen else 'not measured', '; '.join(parts) or 'no ideal sweep')


def claim_d(rep, ideal):
    paper = 'In 96×48, DPO with 2,048 robots performs about as well as CRW with 8,192'
    for folder in ideal:
        p = finals(folder)
        if ('96x48', 'dpo', 2048) in p and ('96x48', 'crw', 8192) in p:
            d, c = p[('96x48', 'dpo', 2048)][0], p[('96x48', 'crw', 8192)][0]
            rel = abs(d - c) / c if c else float('inf')
            rep.claim('d', paper, 'final P within 15 % of each other', 'agrees' if rel <= 0.15 else 'disagrees',
                      'DPO N = 2,048: %.0f; CRW N = 8,192: %.0f (difference %.0f %%)' % (d, c, 100 * rel))
            return
    rep.claim('d', paper, 'final P within 15 % of each other', 'not measured',
              'needs the 96×48 sweep to N = 8,192 (`make paper`); paper-quick stops earlier')


def claim_e(rep, tv):
    paper = 'Under V2 (step_down) GP-DPO is the most reactive and adaptive, and reactivity grows with beta'
    if tv is None:
        rep.claim('e', paper, '—', 'not measured', 'no time-varying sweep')
        return
    rows = [r for r in runs.sweep_table(tv, 'flexibility') if r['valid'] == '1' and r['waveform'] == 'step_down']
    if not rows:
        rep.claim('e', paper, '—', 'not measured', 'no valid step_down rows in %s' % tv)
        return
    mean = {m: {c: [float(r[m]) for r in rows if r['controller'] == c] for c in PAPER} for m in ('R', 'A')}
    avg = {m: {c: sum(v) / len(v) for c, v in mean[m].items() if v} for m in mean}
    lowest = {m: min(avg[m], key=avg[m].get) for m in avg}
    trend = {}
    for c in PAPER:
        for m in ('R', 'A'):
            rhos = []
            for n in sorted({int(r['N']) for r in rows}):
                pts = sorted((float(r['beta']), float(r[m])) for r in rows if r['controller'] == c and int(r['N']) == n)
                rho = spearman([b for b, _ in pts], [v for _, v in pts])
                if not math.isnan(rho):
                    rhos.append(rho)
            trend[(c, m)] = sum(rhos) / len(rhos) if rhos else float('nan')
    r_text = ', '.join('%s %.1f' % (label(c), v) for c, v in avg['R'].items())
    a_text = ', '.join('%s %.1f' % (label(c), v) for c, v in avg['A'].items())
    for tag, m, word in (('e1', 'R', 'reactive'), ('e2', 'A', 'adaptive')):
        rep.claim(tag, 'Under V2 (step_down) GP-DPO is the most %s (lowest %s)' % (word, m),
                  'GP-DPO has the lowest mean %s over every (N, beta) of step_down' % m,
                  'agrees' if lowest[m] == 'gp_dpo' else 'disagrees', 'mean %s: %s' % (m, r_text if m == 'R' else a_text))
    for tag, m in (('e3', 'R'), ('e4', 'A')):
        values = {c: v for (c, mm), v in trend.items() if mm == m and not math.isnan(v)}
        rep.claim(tag, 'Under V2, every controller becomes more %s (lower %s) as beta grows' % (
                  'reactive' if m == 'R' else 'adaptive', m),
                  'the mean Spearman rank correlation of %s with beta (over the N of the sweep) is negative for '
                  'every controller' % m,
                  ('agrees' if all(v < 0 for v in values.values()) else 'disagrees') if values else 'not measured',
                  'correlation: ' + ', '.join('%s %+.2f' % (label(c), v) for c, v in values.items()))


def record_quirks(path):
    """The quirks of the record at `path` (its world/run_info's world and controller constants), or None when
    it holds no run_info."""
    import rosbag
    with rosbag.Bag(path) as bag:
        info = next((m for _, m, _ in bag.read_messages(topics=['/world/run_info'])), None)
    if info is None:
        return None
    out = set()
    for word in (info.world_constants + ' ' + info.controller_constants).split():
        if word.startswith('quirks='):
            out.update(q for q in word[len('quirks='):].split(',') if q)
    return out


def model_of(quirks):
    """A set of quirks as the model it is: 'swarm_forage', 'fordyca_2019', either with '+ extra quirks', or
    with '- quirks left out' when it lacks some of fordyca_2019's."""
    listing = experiment.models()
    fordyca = {q['name'] for q in listing['quirks'] if q['fordyca_2019']}
    order = [q['name'] for q in listing['quirks']]
    if quirks >= fordyca:
        model, extra = 'fordyca_2019', quirks - fordyca
    else:
        model, extra = listing['default'], quirks
    names = [q for q in order if q in extra] + sorted(extra - set(order))
    return model + (' + ' + ', '.join(names) if names else '')


def models_used(folders):
    """(lines for the report, {model: records}) of every planned record of the sweep folders."""
    used, unreadable = {}, 0
    for folder in folders:
        paths = sorted(glob.glob(os.path.join(folder, 'plan', '*.bag'))) or \
            sorted(glob.glob(os.path.join(folder, 'runs', '*.bag')))
        for path in paths:
            try:
                quirks = record_quirks(path)
            except Exception:  # rosbag raises several kinds; the sweep has verified its records
                quirks = None
            if quirks is None:
                unreadable += 1
                continue
            used[model_of(quirks)] = used.get(model_of(quirks), 0) + 1
    if not used:
        return ['**Model:** not known (no record with a world/run_info in the sweeps).', ''], used
    total = sum(used.values())
    where = 'read from the world/run_info of the %d records of the sweeps%s' % (
        total, ' (%d without one)' % unreadable if unreadable else '')
    if len(used) == 1:
        model = next(iter(used))
        what = ' (the default: no quirk)' if model == experiment.models()['default'] else \
            ' (FORDYCA 2019\'s quirks, docs/FIDELITY.md)' if model.startswith('fordyca_2019') else ''
        return ['**Model:** %s%s; %s.' % (model, what, where), ''], used
    return ['**Models: mixed**, %s: %s. The claims below pool them.' % (
        where, '; '.join('%s: %d records' % kv for kv in sorted(used.items()))), ''], used


def every_controller(ideal):
    """Final P of every controller the ideal sweeps ran, the paper's and any other (a plugin's) alike."""
    p = {}
    for folder in ideal:
        p.update(finals(folder))
    order = list(experiment.controller_names())
    controllers = sorted({c for (_, c, _) in p}, key=lambda c: (order.index(c) if c in order else len(order), c))
    if not controllers:
        return []
    out = ['## Every controller measured', '', 'Final P (mean ± 95 % CI over runs) of the ideal sweeps.', '',
           '| arena | N | ' + ' | '.join(label(c) for c in controllers) + ' |',
           '|---|---|' + '---|' * len(controllers)]
    for arena, n in sorted({(a, n) for (a, _, n) in p}):
        cells = ['%.1f ± %.1f' % p[(arena, c, n)][:2] if (arena, c, n) in p else '—' for c in controllers]
        out.append('| %s | %d | %s |' % (arena, n, ' | '.join(cells)))
    return out + ['']


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='example:\n  paper_report.py --ideal results/paper_quick/ideal_32x16 '
                                        '--output report.md   # what `paper` calls')
    ap.add_argument('--ideal', nargs='+', required=True, help='ideal-condition sweep folders')
    ap.add_argument('--time-varying', help='the time-varying sweep folder')
    ap.add_argument('--robustness', nargs='+', default=[], help='robustness sweep folders (noise, population '
                    'dynamics): the section "Beyond the paper: robustness"')
    ap.add_argument('--figures', help='folder of plot_sweep.py figures to show (relative links)')
    ap.add_argument('--output', required=True, help='the markdown file to write')
    ap.add_argument('--title', default='swarm_forage: the paper\'s claims, measured', help='(default: %(default)s)')
    ap.add_argument('--note', default='', help='a line on how the data was made (seeds, sizes, time)')
    a = ap.parse_args(argv)
    rep = Report()
    claim_a(rep, a.ideal)
    claim_b(rep, a.ideal)
    claim_c(rep, a.ideal)
    claim_d(rep, a.ideal)
    claim_e(rep, a.time_varying)
    out = ['# ' + a.title, '']
    model_lines, used = models_used(a.ideal + ([a.time_varying] if a.time_varying else []) + a.robustness)
    out += model_lines
    if a.note:
        out += [a.note, '']
    out += ['| claim | verdict |', '|---|---|'] + ['| (%s) | %s |' % v for v in rep.verdicts] + ['']
    out += rep.lines
    out += every_controller(a.ideal)
    robustness, beyond = robustness_report.section(a.robustness, label) if a.robustness else ([], [])
    out += robustness
    if a.figures:
        base = os.path.dirname(os.path.abspath(a.output))
        out += ['## Figures', '']
        for root, _, files in sorted(os.walk(a.figures)):
            for f in sorted(files):
                if f.endswith('.png'):
                    rel = os.path.relpath(os.path.join(root, f), base)
                    out += ['![%s](%s)' % (f[:-4].replace('_', ' '), rel), '']
    with open(a.output, 'w') as f:
        f.write('\n'.join(out) + '\n')
    print(a.output)
    print('model: %s' % ('; '.join('%s (%d records)' % kv for kv in sorted(used.items())) or 'not known'))
    for tag, verdict in rep.verdicts:
        print('(%s) %s' % (tag, verdict))
    for what, verdict in beyond:
        print('%s: %s' % (what, verdict))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
