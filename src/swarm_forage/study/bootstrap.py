"""A sweep's bootstrap over seeds, read one way for every script (paper_report.py, plot_sweep.py, recommend).

`run_tables` (and so `sweep`) writes DIR/tables/bootstrap.csv: one row per draw and group. Draw 0 is the
groups as measured (every seed once; its values equal the other tables'); in draws 1 ... B every group's
runs are resampled with replacement, each group on its own, and P, e, Z, R and A are recomputed from the
resampled means against the resampled references of the same draw (docs/metrics.md, Bootstrap). So any
function of several groups' metrics (a claim's margin) has its own bootstrap distribution: compute it
draw by draw, then take interval() of the draws 1 ... B.
"""
import csv
import math
import os
from collections import defaultdict

METRICS = ('P', 'e', 'Z', 'R', 'A')  # P: the group's mean final P; Z: Z_mean; e against the next smaller N


class BootstrapMissing(Exception):
    pass


class Draws:
    """The bootstrap of one or more sweeps: values[(arena, controller, N, waveform, beta)][metric] is a list
    indexed by draw (None where the metric is undefined in that draw)."""

    def __init__(self):
        self.values = defaultdict(dict)
        self.runs = {}  # group -> number of seeds
        self.draws = 0  # B (draws 1 ... B; draw 0 is the measurement)

    def groups(self):
        return sorted(self.values)

    def metric(self, group, name):
        """The list of `name` over draws 0 ... B for `group`, or None when the group or metric is absent."""
        return self.values.get(group, {}).get(name)


def group_key(row):
    """(arena, controller, N, waveform, beta) of a bootstrap.csv row; ideal groups have waveform 'null'."""
    return (row['arena'], row['controller'], int(row['N']), row['waveform'], float(row['beta']))


def by_identity(row):
    """A bootstrap.csv row's group named by its identity (unique, where group_key is not: models, noise)."""
    return row['identity']


def read(folders, exclude_identities=(), identities=None, key=group_key):
    """The Draws of the sweep folders (FOLDER/tables/bootstrap.csv each), without the groups whose identity
    is in exclude_identities (e.g. a robustness sweep's groups under noise, which share the plain groups'
    key), and with `identities` only those groups (e.g. one model of a sweep with a models axis, whose groups
    also share the key); `key` names a group by its row (default group_key; by_identity names it by its
    identity). Raises BootstrapMissing naming the first folder without one (run `sweep` again, or run_tables
    bootstrap:=2000)."""
    out = Draws()
    for folder in [folders] if isinstance(folders, str) else folders:
        path = os.path.join(folder, 'tables', 'bootstrap.csv')
        if not os.path.isfile(path):
            raise BootstrapMissing('%s: no bootstrap (run `sweep` on it again, or `run_tables %s bootstrap:=2000`)'
                                   % (path, os.path.join(folder, 'runs')))
        with open(path) as f:
            for row in csv.DictReader(f):
                if row.get('identity') in exclude_identities or \
                        (identities is not None and row.get('identity') not in identities):
                    continue
                name_of, draw = key(row), int(row['draw'])
                out.runs[name_of] = int(row['runs'])
                out.draws = max(out.draws, draw)
                for name in METRICS:
                    column = out.values[name_of].setdefault(name, [])
                    while len(column) <= draw:
                        column.append(None)
                    column[draw] = float(row[name]) if row[name] not in ('', 'nan') else None
    return out


def percentile(sorted_values, q):
    """The q-quantile (0 <= q <= 1) of sorted values, linearly interpolated."""
    if not sorted_values:
        return float('nan')
    pos = q * (len(sorted_values) - 1)
    lo = int(math.floor(pos))
    hi = min(lo + 1, len(sorted_values) - 1)
    return sorted_values[lo] + (sorted_values[hi] - sorted_values[lo]) * (pos - lo)


def interval(column, level=0.95):
    """(estimate, low, high, defined draws) of a column over draws 0 ... B: the estimate is draw 0, the
    interval the percentile interval of draws 1 ... B (NaN when fewer than 2 are defined)."""
    estimate = column[0] if column and column[0] is not None else float('nan')
    draws = sorted(v for v in column[1:] if v is not None and not math.isnan(v))
    if len(draws) < 2:
        return estimate, float('nan'), float('nan'), len(draws)
    tail = (1.0 - level) / 2.0
    return estimate, percentile(draws, tail), percentile(draws, 1.0 - tail), len(draws)


def spread(column):
    """The standard deviation of draws 1 ... B (the bootstrap standard error), NaN with fewer than 2."""
    draws = [v for v in column[1:] if v is not None and not math.isnan(v)]
    if len(draws) < 2:
        return float('nan')
    m = sum(draws) / len(draws)
    return math.sqrt(sum((v - m) ** 2 for v in draws) / (len(draws) - 1))
