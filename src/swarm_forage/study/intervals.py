"""The interval of every point plot_sweep.py draws, computed one way (and tested: test/python/test_sweep_figures.py).

e, Z, R, A and final P against N or beta: the 95 % percentile interval of the sweep's bootstrap over seeds
(DIR/tables/bootstrap.csv through swarm_forage.study.bootstrap). The point itself is the table's value (the
bootstrap's draw 0). A point gets no interval, and says why, when the sweep has no bootstrap.csv, its group
has fewer than 2 seeds, or the metric is undefined in the resamples. An interval of a count (P) never goes
below zero. P(N, t) bands are series.csv's Student t intervals, also clipped at zero.
"""
import math
from collections import namedtuple

from swarm_forage.study import bootstrap

LEVEL = 0.95
CAPTION = '95 % bootstrap interval over seeds'
T_CAPTION = '95 % Student t interval over seeds, clipped at 0'
NO_BOOTSTRAP = 'no interval: no bootstrap.csv'


class Interval(namedtuple('Interval', 'estimate lo hi seeds note')):
    """A plotted point: its value, its interval (NaN when none) and why it has none (note, else None)."""

    @property
    def drawn(self):
        return self.note is None


def _finite(v):
    return v is not None and not math.isnan(v)


def seeds_note(seeds):
    return 'no interval: %d seed' % seeds if seeds == 1 else 'no interval: %d seeds' % seeds


def point_interval(draws, group, metric, estimate=None, seeds=None, count=False, level=LEVEL):
    """The Interval of `metric` ('P', 'e', 'Z', 'R' or 'A') of `group` (arena, controller, N, waveform, beta)
    in the bootstrap.Draws `draws` (None: the sweep has none). `estimate` is the table's value (default the
    bootstrap's draw 0); `seeds` the group's seed count (default the bootstrap's). A count (count=True, P)
    has its interval clipped at 0."""
    column = draws.metric(group, metric) if draws is not None else None
    if seeds is None:
        seeds = draws.runs.get(group, 0) if draws is not None else 0
    if estimate is None:
        estimate = column[0] if column and column[0] is not None else float('nan')
    nan = float('nan')
    if draws is None:
        return Interval(estimate, nan, nan, seeds, NO_BOOTSTRAP)
    if seeds < 2:
        return Interval(estimate, nan, nan, seeds, seeds_note(seeds))
    if column is None:
        return Interval(estimate, nan, nan, seeds, 'no interval: not in bootstrap.csv')
    _, lo, hi, defined = bootstrap.interval(column, level)
    if not (_finite(lo) and _finite(hi)):
        return Interval(estimate, nan, nan, seeds, 'no interval: undefined in %d of %d resamples'
                        % (len(column) - 1 - defined, len(column) - 1))
    if count:
        lo, hi = max(0.0, lo), max(0.0, hi)
    return Interval(estimate, lo, hi, seeds, None)


def count_band(mean, ci95, seeds):
    """(low, high) of a count's Student t interval mean +- ci95, never below 0; None with fewer than 2 seeds
    or no finite half-width."""
    if seeds < 2 or not _finite(ci95):
        return None
    return max(0.0, mean - ci95), mean + ci95


def seeds_text(counts):
    """'2 seeds' / '2-3 seeds per group' of the groups' seed counts."""
    counts = sorted(set(counts))
    if not counts:
        return 'no seeds'
    if len(counts) == 1:
        return '%d seed%s per group' % (counts[0], '' if counts[0] == 1 else 's')
    return '%d\u2013%d seeds per group' % (counts[0], counts[-1])


def ratio_label(pairs):
    """The y label of e for (N1, N2) pairs: 'e(N/2, N)' when every N1 is N2/2, 'e(N/4, N)' for N/4, ...;
    'e(N1, N), N1 = N/2 or N/4' when they differ."""
    ratios = sorted({n2 / float(n1) for n1, n2 in pairs if n1 > 0})
    words = ['N/%g' % r if r != 1 else 'N' for r in ratios]
    if len(words) == 1:
        return 'Karp-Flatt e(%s, N)' % words[0]
    if not words:
        return 'Karp-Flatt e(N1, N)'
    return 'Karp-Flatt e(N1, N), N1 = %s' % ' or '.join(words)


class SweepIntervals:
    """A sweep folder's bootstrap (draws, or None with `missing` saying why) and the seeds of its groups."""

    def __init__(self, folder, series, exclude_identities=()):
        try:
            self.draws, self.missing = bootstrap.read(folder, exclude_identities), None
        except bootstrap.BootstrapMissing as e:
            self.draws, self.missing = None, str(e)
        self.seeds = {}  # (arena, controller, N, waveform, beta) -> seeds, from series.csv
        for r in series:
            self.seeds[key(r, 'swarm_size')] = int(r['runs'])

    def point(self, group, metric, estimate, seeds, count=False):
        return point_interval(self.draws, group, metric, estimate, seeds, count)


def key(row, size_column):
    """The bootstrap group of a table row whose size is in `size_column` (N2, m_i, N or swarm_size)."""
    return row['arena'], row['controller'], int(row[size_column]), row['waveform'], float(row['beta'])
