"""A sweep's robustness tables (run_tables: tables/robustness.csv per group, tables/robustness_runs.csv per
run) read for figures (plot_sweep.py) and the report (paper_report.py), one way for both.

A point is one setting of one (arena, controller, N): its measure (saa or pd), the setting (noise level and
noise words, or the four rates), the group's value, each run's value by seed (`seeds`; their Spread in
`per_run`) and whether the measure could be computed (valid, status). A PD point also carries the queue
the measure assumes against the runs' records (`queue`: the time out of the swarm and the robots out,
predicted and measured, the outages counted and whether they differ by more than 20 %; None where the
table has no value). A PD setting's `family` is the set
of its non-zero rates (death only, malfunction and repair, all four, ...) and its `multiplier` its rates'
sum over the smallest of its family in the table (the base of the experiment file: x1)."""
import math
import os
from collections import defaultdict

from swarm_forage.bags import runs

RATES = ('death', 'birth', 'malfunction', 'repair')
FAMILY_NAMES = {('death',): 'death only', ('malfunction', 'repair'): 'malfunction only',
                ('birth', 'death', 'malfunction', 'repair'): 'all four', ('death', 'malfunction', 'repair'):
                'death, malfunction'}
# Two-sided 95 % t quantiles by degrees of freedom (more: 1.96).
T95 = {1: 12.706, 2: 4.303, 3: 3.182, 4: 2.776, 5: 2.571, 6: 2.447, 7: 2.365, 8: 2.306, 9: 2.262, 10: 2.228,
       12: 2.179, 15: 2.131, 20: 2.086, 25: 2.060, 30: 2.042, 40: 2.021, 60: 2.000, 120: 1.980}


def t95(dof):
    if dof < 1:
        return float('nan')
    return T95.get(dof) or next((T95[k] for k in sorted(T95) if k >= dof), 1.96)


class Spread:
    """Mean, sample standard deviation, 95 % confidence half-width, minimum and maximum of values."""

    def __init__(self, values):
        self.values = list(values)
        self.n = len(self.values)
        self.mean = sum(self.values) / self.n if self.n else float('nan')
        self.sd = math.sqrt(sum((v - self.mean) ** 2 for v in self.values) / (self.n - 1)) if self.n > 1 else 0.0
        self.ci95 = t95(self.n - 1) * self.sd / math.sqrt(self.n) if self.n > 1 else float('nan')
        self.low = min(self.values) if self.values else float('nan')
        self.high = max(self.values) if self.values else float('nan')


def family(point):
    """The non-zero rates of a PD point, sorted by name."""
    return tuple(sorted(r for r in RATES if point['rates'][r] > 0))


def family_name(fam):
    return FAMILY_NAMES.get(fam, ', '.join(fam))


def _float(row, key, default=0.0):
    text = row.get(key, '')
    return float(text) if text not in ('', None) else default


QUEUE = ('time_out_queue', 'time_out_measured', 'out_queue', 'out_measured', 'outages', 'queue_differs')


def _queue(row):
    """The queue fields of a robustness.csv row, None where empty (or absent: a table older than them)."""
    out = {k: (float(row[k]) if row.get(k) not in ('', None) else None) for k in QUEUE}
    if out['queue_differs'] is not None:
        out['queue_differs'] = out['queue_differs'] == 1.0
    return out


def read(folder):
    """The robustness points (dicts) of a sweep folder, empty when it has no robustness table (a sweep
    without noise or population dynamics). Raises runs.TableMissing when the sweep has no tables at all."""
    try:
        groups = runs.sweep_table(folder, 'robustness')
    except runs.TableMissing:
        runs.sweep_table(folder, 'series')  # no tables at all: the sweep did not finish
        return []
    try:
        per_run = runs.sweep_table(folder, 'robustness_runs')
    except runs.TableMissing:
        per_run = []
    by_group = defaultdict(dict)  # (identity, measure) -> seed -> (value, normalized)
    for r in per_run:
        if r.get('valid') == '1':
            by_group[(r['identity'], r['measure'])][int(r['seed'])] = (float(r['value']), float(r['normalized']))
    points = []
    for r in groups:
        p = dict(arena=r['arena'], controller=r['controller'], N=int(r['N']), measure=r['measure'],
                  waveform=r.get('waveform', 'null'), noise=r.get('noise', ''),
                  noise_level=_float(r, 'noise_level'), rates={k: _float(r, k) for k in RATES},
                  max_size=r.get('max_size', ''), T=_float(r, 'T'), T_bar=_float(r, 'T_bar', float('nan')),
                  P=_float(r, 'P', float('nan')), P_reference=_float(r, 'P_reference', float('nan')),
                  valid=r['valid'] == '1', status=r.get('status', ''), identity=r['identity'],
                  reference=r.get('reference', ''), runs=int(r['runs']) if r.get('runs') else 0,
                  queue=_queue(r))
        p['value'] = _float(r, 'value', float('nan')) if p['valid'] else float('nan')
        p['normalized'] = _float(r, 'normalized', float('nan')) if p['valid'] else float('nan')
        # Each seed's value when the table has them, else the group's one value (seed 0).
        seeds = by_group.get((r['identity'], r['measure'])) or ({0: (p['value'], p['normalized'])} if p['valid']
                                                               else {})
        p['seeds'] = {seed: v for seed, (v, _) in seeds.items()}
        p['seeds_normalized'] = {seed: v for seed, (_, v) in seeds.items()}
        p['per_run'] = Spread(p['seeds'].values())
        p['per_run_normalized'] = Spread(p['seeds_normalized'].values())
        if p['measure'] == 'saa' and p['noise_level'] > 0 or p['measure'] == 'pd' and any(p['rates'].values()):
            points.append(p)
    _multipliers([p for p in points if p['measure'] == 'pd'])
    return points


def _multipliers(points):
    smallest = {}
    for p in points:
        fam = family(p)
        total = sum(p['rates'].values())
        smallest[fam] = min(smallest.get(fam, total), total)
    for p in points:
        p['family'] = family(p)
        p['multiplier'] = round(sum(p['rates'].values()) / smallest[p['family']], 6)


def varied_identities(folder):
    """The identities of a sweep's groups under noise or population dynamics (not the plain runs)."""
    return {p['identity'] for p in read(folder)}


def exists(folder):
    return os.path.isfile(os.path.join(folder, 'tables', 'robustness.csv'))
