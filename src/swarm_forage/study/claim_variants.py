"""Where each of the paper's claims turns, measured: the claims of one or more studies re-evaluated under each
documented choice a reader could make differently, beside the verdict as the report gives it.

    claim_variants STUDY [STUDY ...] --output FILE.md

- **Metric definitions**: every ideal and time-varying sweep's records through `run_tables
  definitions:=authors_code_2019` (the authors' 2019 scripts: docs/metrics.md), into
  STUDY/variants/authors_code_2019/SWEEP/tables, then the claims on those tables.
- **Arena**: claim (c) in each arena on its own (the report takes the smallest margin over arenas).
- **Scale** (claims e1, e2): R and A per block of the ideal run, draw by draw, and A split at the change
  (before and after alpha, from the groups' mean series).
- **Model**: one page per model (its studies); `make claim-variants` writes both models' pages.
- **Thresholds**: where each verdict turns, as the report states it (swarm_forage.study.claims).

The claims, bootstrap and thresholds are the report's (swarm_forage.study.paper_claims); nothing is tuned here.
"""
import argparse
import csv
import math
import os
import subprocess
import sys

from swarm_forage.experiment import kinds
from swarm_forage.study import bootstrap, claims, paper_claims, publish

DEFINITIONS = ('paper', 'authors_code_2019')  # authors_code and authors_code_2020 give e, Z, R, A as 2019's
# Claim (b)'s "first negative Z" on each definitions' Z scale: the paper's Z is in (0, 1), 0.5 where losses grow
# linearly (claims.Z_BELOW allows for rounding); the authors' 2019 Z = 1 - e^theta is negative there.
Z_BELOW = {'paper': claims.Z_BELOW, 'authors_code_2019': 0.0}
CLAIM_SWEEPS = ('ideal_', 'time_varying_')


label = kinds.display_name


def sweeps(studies):
    """The ideal and time-varying sweep folders of the studies that have tables and a plan of records."""
    out = []
    for study in studies:
        for name in sorted(os.listdir(study)):
            folder = os.path.join(study, name)
            if name.startswith(CLAIM_SWEEPS) and os.path.isfile(os.path.join(folder, 'tables', 'bootstrap.csv')) \
                    and os.path.isdir(os.path.join(folder, 'plan')):
                out.append(folder)
    return out


def sample_interval(folder):
    with open(os.path.join(folder, 'tables', 'series.csv')) as f:
        return int(next(csv.DictReader(f))['sample_interval'])


def variant(folder, definitions):
    """FOLDER's tables under `definitions`: FOLDER itself for the paper's, else STUDY/variants/DEFS/SWEEP, made
    by run_tables on FOLDER/plan when it has no bootstrap yet (it is kept: a rerun reads it)."""
    if definitions == 'paper':
        return folder
    study, name = os.path.split(folder)
    out = os.path.join(study, 'variants', definitions, name)
    if not os.path.isfile(os.path.join(out, 'tables', 'bootstrap.csv')):
        print('claim_variants: run_tables %s definitions:=%s' % (folder, definitions), flush=True)
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', os.path.join(folder, 'plan'),
                               'out:=' + os.path.join(out, 'tables'), 'definitions:=' + definitions,
                               'sample_interval:=%d' % sample_interval(folder)],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if proc.returncode != 0:
            raise SystemExit('claim_variants: run_tables on %s failed (exit %d): %s'
                             % (folder, proc.returncode, proc.stderr.strip()[-400:]))
    return out


def evaluate(folders, definitions):
    """{tag: Claim} of the ideal folders and the time-varying one among `folders` (tables of `definitions`)."""
    ideal = [f for f in folders if os.path.basename(f).startswith('ideal_')]
    tv = next((f for f in folders if os.path.basename(f).startswith('time_varying_')), None)
    claim_list, _ = paper_claims.evaluate(ideal, tv, label, Z_BELOW[definitions])
    return {c.tag: c for c in claim_list}


def per_arena_c(folders):
    """{arena: Claim (c)} with each arena's ideal sweeps on their own."""
    draws = paper_claims.read_draws([f for f in folders if os.path.basename(f).startswith('ideal_')])
    arenas = sorted({g[0] for d in draws.values() if d for g in d.groups() if g[3] == 'null'},
                    key=lambda a: [int(x) for x in a.split('x')])
    out = {}
    for arena in arenas:
        c = paper_claims.claim_c({f: d for f, d in draws.items() if d and any(g[0] == arena for g in d.groups())},
                                 label)[0]
        if c.verdict != 'not measured':
            out[arena] = c
    return out


TICKS_PER_SECOND = 5  # series.csv gives alpha in simulated seconds, tick_end in ticks


def per_ideal_block(tv, folder):
    """The time-varying sweep's Draws with R and A divided, draw by draw, by the final P of the same draw's ideal
    group (same controller, arena, N): distances per block the swarm delivers without the change, so a controller
    that delivers more is not farther from its curve for that alone. Not the paper's or the authors' code's."""
    out = bootstrap.Draws()
    out.runs, out.draws = dict(tv.runs), tv.draws
    for g, metrics in tv.values.items():
        ideal = tv.values.get((g[0], g[1], g[2], 'null', 0.0), {}).get('P')
        out.values[g] = dict(metrics)
        if g[3] == 'null' or ideal is None:
            continue
        for m in ('R', 'A'):
            out.values[g][m] = [None if v is None or not p else v / p for v, p in zip(metrics[m], ideal)]
    return {folder: out}


def dtw(x, y):
    """1-D dynamic time warping with cost |x - y| (the paper definitions' DTW, docs/metrics.md)."""
    inf = float('inf')
    prev = [0.0] + [inf] * len(y)
    for a in x:
        row = [inf]
        for j, b in enumerate(y):
            row.append(abs(a - b) + min(prev[j], prev[j + 1], row[j]))
        prev = row
    return prev[-1]


def adaptability_halves(tv_folder):
    """{(controller, N, beta): (A as the table gives it, A recomputed, A before alpha, A after alpha)} of the
    step_down groups, from the group means in series.csv: P_A* is the ideal group's p wherever s <= 1 (Eqs 9-10),
    so under a step down it is the ideal p throughout and A counts the throttled half as well as the recovery."""
    series, table = {}, {}
    with open(os.path.join(tv_folder, 'tables', 'series.csv')) as f:
        for r in csv.DictReader(f):
            key = (r['controller'], int(r['swarm_size']), r['waveform'], float(r['beta']))
            series.setdefault(key, []).append((int(r['sample']), float(r['p_mean']), int(r['tick_end']),
                                               float(r['alpha'])))
    with open(os.path.join(tv_folder, 'tables', 'flexibility.csv')) as f:
        for r in csv.DictReader(f):
            if r['waveform'] == 'step_down' and r['A'] not in ('', 'nan'):
                table[(r['controller'], int(r['N']), float(r['beta']))] = float(r['A'])
    out = {}
    for (ctl, n, beta), a in table.items():
        run, ideal = sorted(series.get((ctl, n, 'step_down', beta), [])), sorted(series.get((ctl, n, 'null', 0.0), []))
        if not run or len(run) != len(ideal):
            continue
        p, q = [x[1] for x in run], [x[1] for x in ideal]
        k = sum(1 for x in run if x[2] < x[3] * TICKS_PER_SECOND)  # the samples before alpha
        out[(ctl, n, beta)] = (a, dtw(q, p), dtw(q[:k], p[:k]), dtw(q[k:], p[k:]))
    return out


def halves_lines(halves):
    """The (e2)/(e4) section: each controller's mean rank correlation of A with beta, whole run and each half,
    and the relative A after alpha (point estimates from the group means)."""
    if not halves:
        return []
    ctls = [c for c in claims.PAPER if any(k[0] == c for k in halves)]
    sizes = sorted({k[1] for k in halves})
    lines = ['## Adaptability, before and after the change (claims e2, e4)', '',
             'Under V2 the first half is throttled (s < 1) and P_A* = the ideal p (Eqs 9–10 raise it only where '
             's > 1), so A = DTW(p_ideal, p) counts the throttled half as well as the recovery. Here A is '
             'recomputed from the group means (series.csv), whole and split at α; point estimates, no '
             'interval. Largest difference between the recomputed and the table A: %.2g.' % max(
                 abs(v[0] - v[1]) for v in halves.values()), '',
             '| controller | mean ρ(A, β), whole run | before α | after α | share of A before α | mean relative A '
             'after α |', '|---|---|---|---|---|---|']
    cells = sorted({(k[1], k[2]) for k in halves if all((c, k[1], k[2]) in halves for c in ctls)})

    def rel(c):
        return sum(halves[(c, n, b)][3] / (sum(halves[(x, n, b)][3] for x in ctls) / len(ctls) or 1.0)
                   for n, b in cells) / max(1, len(cells))
    for c in ctls:
        rhos = []
        for part in (1, 2, 3):
            values = [claims.spearman([b for nn, b in cells if nn == n], [halves[(c, n, b)][part]
                                                                        for nn, b in cells if nn == n])
                      for n in sizes]
            values = [v for v in values if not math.isnan(v)]
            rhos.append(sum(values) / len(values) if values else float('nan'))
        share = sum(halves[(c, n, b)][2] for n, b in cells) / max(1e-12, sum(halves[(c, n, b)][1] for n, b in cells))
        lines.append('| %s | %+.2f | %+.2f | %+.2f | %.0f %% | %.3f |' % (label(c), rhos[0], rhos[1], rhos[2],
                                                                         100 * share, rel(c)))
    return lines + ['']


def cell(c):
    if c is None:
        return '—'
    if c.verdict == 'not measured':
        return 'not measured'
    return '**%s** %s = %.3g [%.3g, %.3g]' % (c.verdict, c.quantity, c.estimate, c.low, c.high) \
        if not math.isnan(c.estimate) else '**%s**' % c.verdict


def table(columns):
    """Markdown rows: claim | paper's sentence | one column per (name, {tag: Claim})."""
    tags = list(next(iter(columns.values())).keys())
    head = '| claim | the paper | ' + ' | '.join(columns) + ' |'
    out = [head, '|' + '---|' * (2 + len(columns))]
    for tag in tags:
        first = next(iter(columns.values()))[tag]
        out.append('| (%s) | %s | %s |' % (tag, first.paper, ' | '.join(cell(v.get(tag)) for v in columns.values())))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(prog='claim_variants', description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('studies', nargs='+', help='study folders (results/paper_quick, results/paper_96): their '
                    'ideal_* and time_varying_* sweeps are pooled, as one study')
    ap.add_argument('--output', required=True, help='the markdown file to write')
    a = ap.parse_args(argv)
    for s in a.studies:
        if not os.path.isdir(s):
            ap.error('%s is not a folder' % s)
    mine = sweeps(a.studies)
    if not mine:
        ap.error('no ideal or time-varying sweep with tables and a plan in %s' % ', '.join(a.studies))
    columns = {}
    for defs in DEFINITIONS:
        columns['definitions: %s' % defs] = evaluate([variant(f, defs) for f in mine], defs)
    tv = next((f for f in mine if os.path.basename(f).startswith('time_varying_')), None)
    if tv:
        scaled = {c.tag: c for c in paper_claims.claim_e(per_ideal_block(bootstrap.read(tv), tv), label, tv)
                  if c.tag in ('e1', 'e2')}
        columns['R, A per ideal block'] = scaled
    models = sorted({publish.report_model(s) or 'not named' for s in a.studies})
    out = ['# Where the claims turn: %s' % ', '.join(models), '',
           'Made by `rosrun swarm_forage claim_variants %s --output %s`: each claim as the report decides it '
           '(95 %% bootstrap interval over seeds), under each documented choice. Model: %s. Studies: %s.' % (
               ' '.join(a.studies), a.output, ', '.join(models), ', '.join(os.path.relpath(f) for f in mine)), '']
    out += table(columns) + ['']
    base = columns['definitions: paper']
    out += ['## Claim (c), arena by arena', '',
            'The row above takes the smallest margin over every arena measured; here each arena on its own (paper '
            'definitions). The paper makes the claim at 16,384 robots in 96×48, the largest arena.',
            '', '| arena | verdict | evidence |', '|---|---|---|']
    for arena, c in per_arena_c(mine).items():
        out.append('| %s | %s | %s |' % (arena, cell(c), c.evidence))
    out += ['']
    if tv:
        out += halves_lines(adaptability_halves(tv))
    out += ['## Thresholds (paper definitions)', '']
    for tag, c in base.items():
        for s in c.sensitivity:
            out.append('- (%s) %s' % (tag, s))
    authors = columns['definitions: authors_code_2019'].get('b')
    if authors and authors.sensitivity:  # the authors' Z has its own scale: where (b) turns on it
        out += ['', 'Claim (b) on the authors\' 2019 Z (1 − e^θ on final values; "first negative Z" is Z < 0):', '',
                '- (b) %s' % authors.sensitivity[0]]
    with open(a.output, 'w') as f:
        f.write('\n'.join(out) + '\n')
    print(a.output)
    for name, col in columns.items():
        print('%s: %s' % (name, ', '.join('(%s) %s' % (t, c.verdict) for t, c in col.items())))
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
