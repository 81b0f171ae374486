"""The paper's claims as margins with bootstrap intervals over seeds (paper_report.py; `paper --decide`).

Each claim is a quantity computed draw by draw from the sweeps' bootstrap (swarm_forage.study.bootstrap: draw 0 as
measured, draws 1 ... B with every group's seeds resampled), compared with a threshold. The verdict is
*agrees* when the whole 95 % percentile interval of the quantity is on the claim's side of the threshold,
*disagrees* when it is wholly on the other side, and *undecided* when it straddles the threshold (or a group
has fewer than MIN_SEEDS seeds: a bootstrap of two seeds has three possible means and cannot stand for the
spread). Where undecided, a normal approximation says how many seeds per group would decide it (normal_seeds):
the count printed in the report, written to --json and used by `paper --decide` (swarm_forage.sweep.rounds).
"""
import math
import operator

from swarm_forage.study import bootstrap

LEVEL = 0.95
Z95 = 1.959963984540054
MIN_SEEDS = 3
Z_BELOW = 0.49    # (b): "Z below 0.5" is Z < 0.49 (a swarm without interference has Z = 0.5 up to rounding)
STEPS = 1         # (b): the two sizes within one step of the power-of-two sizes (a factor of 2)
WITHIN = 0.15     # (d): "about as well": final P within 15 % of CRW's
SHARE = 2.0 / 3   # (a2): DPO and GP-DPO each beat CRW at two thirds or more of the sizes N <= SMALL_N
SMALL_N = 64
PAPER = ('crw', 'dpo', 'gp_dpo')  # the controllers the paper's claims are about (kinds of the registry)
OPS = {'<': operator.lt, '<=': operator.le, '>': operator.gt, '>=': operator.ge}


class Claim:
    """One claim's verdict: the quantity (estimate, interval), threshold, seeds and what it used."""

    def __init__(self, tag, paper, criterion, quantity=None):
        self.tag, self.paper, self.criterion, self.quantity = tag, paper, criterion, quantity
        self.verdict, self.evidence, self.missing = 'not measured', '', ''
        self.op = self.threshold = None
        self.estimate = self.low = self.high = self.se = float('nan')
        self.defined = self.draws = 0
        self.seeds = {}          # group -> seeds
        self.seeds_needed = None  # undecided: MIN_SEEDS under it, else normal_seeds (None: no spread or gap)
        self.sensitivity = []    # lines: each threshold and where the verdict turns
        self.groups = []         # (folder, arena, controller, N, waveform, beta)

    def seeds_text(self):
        if not self.seeds:
            return '—'
        lo, hi = min(self.seeds.values()), max(self.seeds.values())
        return '%d' % lo if lo == hi else '%d–%d' % (lo, hi)

    def fewest(self):
        """The fewest seeds of the claim's groups: the n of normal_seeds."""
        return min(self.seeds.values()) if self.seeds else 0

    def seeds_words(self):
        """What the report says of the seeds that would decide an undecided claim (the number is seeds_needed,
        the one `paper --decide` raises its groups to, at least one more and at most the cap)."""
        n = self.fewest()
        if n < MIN_SEEDS:
            return ('fewer than %d seeds in a group: no interval to decide by; at least %d would give one'
                    % (MIN_SEEDS, MIN_SEEDS))
        if self.defined < 0.5 * max(1, self.draws):
            return ('the quantity is defined in only %d of %d draws: no interval to decide by (`paper --decide` '
                    'doubles the seeds)' % (self.defined, self.draws))
        gap = abs(self.estimate - self.threshold)
        if self.seeds_needed is None:
            return ('the interval straddles the threshold; the estimate is on it or the draws have no spread, so '
                    'no normal approximation (`paper --decide` doubles the seeds)')
        formula = "n′ = n·(1.96·se / |estimate − threshold|)² = %d·(1.96·%.4g / %.4g)² = %.3g" % (
            n, self.se, gap, n * (Z95 * self.se / gap) ** 2)
        if self.seeds_needed > n:
            return ('the interval straddles the threshold; a normal approximation, %s, says about %d seeds per '
                    'group would decide it' % (formula, self.seeds_needed))
        return ('the interval straddles the threshold, yet a normal approximation, %s, is no more than the %d seeds '
                'it has: the estimate is %.1f standard errors from the threshold while the percentile interval '
                'reaches it (the draws are skewed or discrete), so it cannot say how many would decide it '
                '(`paper --decide` adds one seed a round, up to the cap)' % (formula, n, gap / self.se))

    def seeds_short(self):
        """The verdict table's words on the seeds that would decide an undecided claim ('' when none)."""
        if self.verdict != 'undecided' or self.seeds_needed is None:
            return ''
        if self.fewest() < MIN_SEEDS or self.seeds_needed > self.fewest():
            return ' (≈ %d seeds)' % self.seeds_needed
        return ' (normal approximation %d ≤ %d seeds: skewed draws)' % (self.seeds_needed, self.fewest())

    def as_json(self):
        def num(v):
            return None if v is None or (isinstance(v, float) and math.isnan(v)) else v
        return {'claim': self.tag, 'verdict': self.verdict, 'quantity': self.quantity, 'op': self.op,
                'threshold': self.threshold, 'margin': num(self.estimate), 'low': num(self.low),
                'high': num(self.high), 'seeds': sorted(set(self.seeds.values())),
                'seeds_needed': self.seeds_needed, 'groups': [list(g) for g in self.groups]}


def normal_seeds(n, se, gap):
    """n' = n (Z95 se / gap)^2 rounded up: the seeds per group at which the normal interval estimate +- Z95 se',
    se' = se sqrt(n / n'), would just reach the threshold `gap` away (docs/decisions.md); None without a spread
    or a gap. It can be n or fewer: the estimate is then more than Z95 se from the threshold while the
    percentile interval still reaches it (draws skewed or discrete), and the approximation cannot tell."""
    if not gap > 0 or not se > 0 or n < 1:
        return None
    return int(math.ceil(n * (Z95 * se / gap) ** 2 - 1e-9))


def decide(claim, column, op, threshold, used, draws):
    """Sets claim's estimate, interval and verdict from `column` (the quantity per draw) against `threshold`
    (the claim holds where `quantity op threshold`); `used`: {(folder, group)} of the groups it read."""
    claim.op, claim.threshold = op, threshold
    claim.groups = sorted((f,) + g for f, g in used)
    claim.seeds = {g: draws[f].runs.get(g, 0) for f, g in used}
    claim.estimate, claim.low, claim.high, claim.defined = bootstrap.interval(column, LEVEL)
    claim.draws = len(column) - 1
    claim.se = bootstrap.spread(column)
    holds = OPS[op]
    few = min(claim.seeds.values()) if claim.seeds else 0
    if math.isnan(claim.estimate):
        claim.verdict = 'not measured'
        return
    if few < MIN_SEEDS or claim.defined < 0.5 * max(1, claim.draws):
        claim.verdict = 'undecided'
        claim.seeds_needed = MIN_SEEDS if few < MIN_SEEDS else None
        return
    if holds(claim.low, threshold) and holds(claim.high, threshold):
        claim.verdict = 'agrees'
    elif not holds(claim.low, threshold) and not holds(claim.high, threshold):
        claim.verdict = 'disagrees'
    else:
        claim.verdict = 'undecided'
        claim.seeds_needed = normal_seeds(few, claim.se, abs(claim.estimate - threshold))


def per_draw(draws, folder_groups, function, measured_only=False):
    """function(values) for every draw (only draw 0, the measurement, with measured_only), where
    values[group] = {metric: value}; None where it returns None or a value it needs is undefined."""
    folders = {f for f, _ in folder_groups}
    total = 0 if measured_only else min(draws[f].draws for f in folders) if folders else 0
    out = []
    for d in range(total + 1):
        values = {}
        for f, g in folder_groups:
            values[g] = {m: (draws[f].values[g][m][d] if d < len(draws[f].values[g][m]) else None)
                         for m in bootstrap.METRICS}
        try:
            out.append(function(values))
        except (KeyError, TypeError, ZeroDivisionError, ValueError):
            out.append(None)
    return out


def measured_values(draws, folder_groups):
    """values[group] = {metric: value} of the measurement (draw 0)."""
    return per_draw(draws, folder_groups, lambda v: v, measured_only=True)[0]


def groups_of(draws, folders, arena, ideal=True):
    """[(folder, group)] of `arena`'s ideal (or non-ideal) groups in the folders' bootstraps."""
    return [(f, g) for f in folders for g in draws[f].groups()
            if g[0] == arena and (g[3] == 'null') == ideal]


def ranks(values):
    """Average ranks (1 ... n): tied values share the mean of the ranks they span."""
    order = sorted(range(len(values)), key=lambda i: values[i])
    out = [0.0] * len(values)
    i = 0
    while i < len(order):
        j = i
        while j + 1 < len(order) and values[order[j + 1]] == values[order[i]]:
            j += 1
        for k in range(i, j + 1):
            out[order[k]] = (i + j) / 2.0 + 1
        i = j + 1
    return out


def spearman(xs, ys):
    """Spearman's rank correlation with ties (Pearson's r of average ranks); NaN under 3 points or no spread."""
    if len(xs) < 3:
        return float('nan')
    rx, ry = ranks(xs), ranks(ys)
    mx, my = sum(rx) / len(rx), sum(ry) / len(ry)
    num = sum((a - mx) * (b - my) for a, b in zip(rx, ry))
    den = math.sqrt(sum((a - mx) ** 2 for a in rx) * sum((b - my) ** 2 for b in ry))
    return num / den if den else float('nan')


def turning(evaluate, grid, name, fmt='%.3f'):
    """A sensitivity line: the verdict on the measurement (draw 0) over a grid of one threshold's values,
    as ranges ('agrees for 0.486 ... 0.500; disagrees for 0.400 ... 0.485')."""
    spans = []
    for v in grid:
        verdict = evaluate(v)
        if spans and spans[-1][0] == verdict:
            spans[-1][2] = v
        else:
            spans.append([verdict, v, v])
    return '%s: the measured values %s' % (name, '; '.join(
        '%s for %s' % (s[0], fmt % s[1] if s[1] == s[2] else (fmt + ' … ' + fmt) % (s[1], s[2])) for s in spans))


def margin_sensitivity(claim, name, fmt='%.3f'):
    """The line for a threshold the quantity is compared with directly: it turns where the threshold passes
    the measured quantity."""
    if math.isnan(claim.estimate):
        return
    claim.sensitivity.append('%s (%s): the measured quantity is %s, so the verdict on the measurement turns at '
                             'a threshold of %s; the interval\'s ends (%s, %s) are where the verdict with '
                             'its uncertainty turns' % (name, fmt % claim.threshold, fmt % claim.estimate,
                                                        fmt % claim.estimate, fmt % claim.low, fmt % claim.high))
