"""The paper's claims (a)-(e), each a quantity per bootstrap draw against a threshold (swarm_forage.study.claims).

evaluate(ideal_folders, tv_folder, label) -> [claims.Claim]; paper_report.py writes them, `paper --decide`
raises the seeds of the groups of undecided ones.
"""
import math

from swarm_forage.study import bootstrap
from swarm_forage.study.claims import (Claim, PAPER, SHARE, SMALL_N, STEPS, WITHIN, Z_BELOW, decide, groups_of,
                                 margin_sensitivity, measured_values, per_draw, spearman,
                                 turning)


# Claim (d)'s groups: DPO at 2,048 and CRW at 8,192 robots in 96x48.
D_SIZES = ('96x48', 2048, 8192)


def read_draws(folders):
    out = {}
    for f in folders:
        try:
            out[f] = bootstrap.read(f)
        except bootstrap.BootstrapMissing:
            out[f] = None
    return out


def _arena_folders(draws, arena):
    return [f for f, d in draws.items() if d is not None and any(g[0] == arena and g[3] == 'null'
                                                                    for g in d.groups())]


def _sizes(used, controller):
    return sorted({g[2] for _, g in used if g[1] == controller})


def _key(used, controller, n):
    return next((g for _, g in used if g[1] == controller and g[2] == n), None)


def claim_a(draws, label):
    """(a1) CRW the most scalable in 32x16; (a2) DPO and GP-DPO better at small N."""
    paper1 = 'In 32×16, CRW is the most scalable (lowest e)'
    paper2 = 'In 32×16, DPO and GP-DPO perform better than CRW at small N'
    folders = _arena_folders(draws, '32x16')
    used = [u for u in groups_of(draws, folders, '32x16') if u[1][1] in PAPER]
    sizes = {c: _sizes(used, c) for c in PAPER}
    out = []
    c1 = Claim('a1', paper1, '', 'm')
    top = sorted(set.intersection(*(set(s) for s in sizes.values())))[-3:] if all(sizes.values()) else []
    top = [n for n in top if n > 1]
    c1.criterion = ('m = min(mean e of DPO, of GP-DPO) − mean e of CRW, e averaged over the three largest N (%s); '
                    'agrees when m > 0' % ', '.join(map(str, top)))
    if len(top) == 3:
        u1 = [u for u in used if u[1][2] in top]

        def m1(v):
            mean = {c: sum(v[_key(u1, c, n)]['e'] for n in top) / 3.0 for c in PAPER}
            return min(mean['dpo'], mean['gp_dpo']) - mean['crw']
        decide(c1, per_draw(draws, u1, m1), '>', 0.0, u1, draws)
        margin_sensitivity(c1, 'threshold of m')
        c1.evidence = 'mean e at N = %s: %s' % (', '.join(map(str, top)), ', '.join(
            '%s %.3f' % (label(c), sum(draws[f].values[g]['e'][0] for f, g in u1 if g[1] == c) / 3.0)
            for c in PAPER))
    else:
        c1.missing = 'no 32×16 sweep with three sizes of every controller'
    out.append(c1)
    c2 = Claim('a2', paper2, '', 's')
    small = [n for n in sorted(set.intersection(*(set(s) for s in sizes.values()))) if n <= SMALL_N] \
        if all(sizes.values()) else []
    c2.criterion = ('s = the smaller of the shares of the sizes N ≤ %d (%s) at which DPO, and GP-DPO, deliver more '
                    'than CRW (mean final P); agrees when s ≥ %.2f' % (SMALL_N, ', '.join(map(str, small)), SHARE))
    if small:
        u2 = [u for u in used if u[1][2] in small]

        def m2(v):
            return min(sum(v[_key(u2, c, n)]['P'] > v[_key(u2, 'crw', n)]['P'] for n in small) / len(small)
                       for c in ('dpo', 'gp_dpo'))
        decide(c2, per_draw(draws, u2, m2), '>=', SHARE, u2, draws)
        margin_sensitivity(c2, 'the share required', '%.2f')
        c2.evidence = 'share of sizes N ≤ %d where the controller beats CRW (measured): %s' % (SMALL_N, ', '.join(
            '%s %d / %d' % (label(c), sum(draws[_f(u2, c, n)].values[_key(u2, c, n)]['P'][0] >
                                          draws[_f(u2, 'crw', n)].values[_key(u2, 'crw', n)]['P'][0]
                                          for n in small), len(small)) for c in ('dpo', 'gp_dpo')))
    else:
        c2.missing = 'no 32×16 sweep with sizes N ≤ %d of every controller' % SMALL_N
    out.append(c2)
    return out


def _f(used, controller, n):
    return next(f for f, g in used if g[1] == controller and g[2] == n)


def claim_b(draws, label, z_below=Z_BELOW):
    """(b) with "first negative Z" as Z < z_below: the paper's Z is in (0, 1) and 0.5 where losses grow
    linearly, so Z_BELOW; the authors' 2019 Z (1 - e^theta) is negative exactly where the paper's is below 0.5."""
    paper = 'In 64×32, for DPO and GP-DPO the N of maximum P ≈ the N of the first Z below 0.5'
    c = Claim('b', paper, 'k = the larger, over DPO and GP-DPO, of the distance in power-of-two steps between the '
              'N of maximum mean final P and the smallest N with Z < %.2f (no such N: 99); agrees when k ≤ %d'
              % (z_below, STEPS), 'k')
    folders = _arena_folders(draws, '64x32')
    used = [u for u in groups_of(draws, folders, '64x32') if u[1][1] in ('dpo', 'gp_dpo')]
    if not all(_sizes(used, x) for x in ('dpo', 'gp_dpo')):
        c.missing = 'no 64×32 ideal sweep of DPO and GP-DPO'
        return [c]

    def steps(v, z_below):
        worst = 0
        for ctl in ('dpo', 'gp_dpo'):
            sizes = _sizes(used, ctl)
            n_max = max(sizes, key=lambda n: v[_key(used, ctl, n)]['P'])
            below = [n for n in sizes if v[_key(used, ctl, n)]['Z'] is not None and v[_key(used, ctl, n)]['Z'] < z_below]
            worst = max(worst, abs(math.log2(n_max) - math.log2(below[0])) if below else 99)
        return worst
    decide(c, per_draw(draws, used, lambda v: steps(v, z_below)), '<=', STEPS, used, draws)
    measured = measured_values(draws, used)
    grid = [round(z_below - 0.09 + 0.001 * k, 3) for k in range(101)]
    c.sensitivity.append(turning(lambda t: 'agrees' if steps(measured, t) <= STEPS else 'disagrees', grid,
                                 'the Z threshold (%.2f)' % z_below))
    c.sensitivity.append('the tolerance of %d step: the measured k is %g, so it turns at a tolerance of %g steps'
                         % (STEPS, c.estimate, c.estimate))
    parts = []
    for ctl in ('dpo', 'gp_dpo'):
        sizes = _sizes(used, ctl)
        n_max = max(sizes, key=lambda n: measured[_key(used, ctl, n)]['P'])
        below = [n for n in sizes if measured[_key(used, ctl, n)]['Z'] is not None and
                 measured[_key(used, ctl, n)]['Z'] < z_below]
        parts.append('%s: max P at N = %d (%.0f blocks), first Z < %.2f at %s' % (
            label(ctl), n_max, measured[_key(used, ctl, n_max)]['P'], z_below,
            'N = %d (Z = %.4f)' % (below[0], measured[_key(used, ctl, below[0])]['Z']) if below else 'no N'))
    c.evidence = '; '.join(parts)
    return [c]


def claim_c(draws, label):
    paper = 'CRW is the best performer at the largest N'
    c = Claim('c', paper, 'r = the smallest, over arenas, of CRW\'s mean final P at the arena\'s largest N (of CRW and another controller) divided '
              'by the best other controller\'s, minus 1; agrees when r > 0', 'r')
    arenas = sorted({g[0] for d in draws.values() if d for g in d.groups() if g[3] == 'null'})
    used, largest = [], {}
    for arena in arenas:
        u = [x for x in groups_of(draws, _arena_folders(draws, arena), arena) if x[1][1] in PAPER]
        both = set(_sizes(u, 'crw')) & set(_sizes(u, 'dpo') + _sizes(u, 'gp_dpo'))
        if not both:
            continue
        n = max(both)  # the largest N with CRW and another controller
        largest[arena] = n
        used += [x for x in u if x[1][2] == n]
    if not used:
        c.missing = 'no ideal sweep with CRW and another controller at the same N'
        return [c]

    def ratio(v):
        worst = math.inf
        for arena, n in largest.items():
            others = [v[g]['P'] for _, g in used if g[0] == arena and g[1] != 'crw']
            crw = next(v[g]['P'] for _, g in used if g[0] == arena and g[1] == 'crw')
            if others:
                worst = min(worst, crw / max(others) - 1.0)
        return worst
    decide(c, per_draw(draws, used, ratio), '>', 0.0, used, draws)
    margin_sensitivity(c, 'threshold of r')
    c.evidence = '; '.join('%s, N = %d: %s' % (arena, n, ', '.join(
        '%s %.0f' % (label(g[1]), draws[f].values[g]['P'][0]) for f, g in used if g[0] == arena))
        for arena, n in sorted(largest.items()))
    return [c]


def claim_d(draws, label, arena=D_SIZES[0], dpo_n=D_SIZES[1], crw_n=D_SIZES[2]):
    """(d) from the groups of DPO at dpo_n and CRW at crw_n in `arena` (the paper's by default; the ablation's
    tests give a small arena)."""
    paper = 'In 96×48, DPO with 2,048 robots performs about as well as CRW with 8,192'
    c = Claim('d', paper, 'q = |P(DPO, {:,}) − P(CRW, {:,})| / P(CRW, {:,}), mean final P; agrees when '
              'q ≤ {:.2f}'.format(dpo_n, crw_n, crw_n, WITHIN), 'q')
    used = [u for u in groups_of(draws, _arena_folders(draws, arena), arena)
            if (u[1][1], u[1][2]) in (('dpo', dpo_n), ('crw', crw_n))]
    if len(used) != 2:
        c.missing = 'needs the {} sweep of DPO at {:,} and CRW at {:,} (`make paper-96`)'.format(
            arena.replace('x', '×'), dpo_n, crw_n)
        return [c]
    dpo = next(g for _, g in used if g[1] == 'dpo')
    crw = next(g for _, g in used if g[1] == 'crw')
    decide(c, per_draw(draws, used, lambda v: abs(v[dpo]['P'] - v[crw]['P']) / v[crw]['P']), '<=', WITHIN,
           used, draws)
    margin_sensitivity(c, 'the 15 % tolerance', '%.3f')
    p = {g: draws[f].values[g]['P'] for f, g in used}
    c.evidence = 'DPO N = {:,}: {:.0f}; CRW N = {:,}: {:.0f} (DPO / CRW = {:.2f})'.format(
        dpo_n, p[dpo][0], crw_n, p[crw][0], p[dpo][0] / p[crw][0])
    return [c]


def claim_e(draws, label, tv):
    out = []
    d = draws.get(tv) if tv else None
    used = [(tv, g) for g in d.groups() if g[3] == 'step_down' and g[1] in PAPER] if d else []
    cells = sorted({(g[2], g[4]) for _, g in used if all((tv, (g[0], c, g[2], g[3], g[4])) in used for c in PAPER)})
    used = [u for u in used if (u[1][2], u[1][4]) in cells]
    arena = used[0][1][0] if used else None

    def at(v, c, n, b, m):
        return v[(arena, c, n, 'step_down', b)][m]
    for tag, m, word in (('e1', 'R', 'reactive'), ('e2', 'A', 'adaptive')):
        c = Claim(tag, 'Under V2 (step_down) GP-DPO is the most %s (lowest %s)' % (word, m),
                  'g = min over CRW and DPO of (their mean relative %s − GP-DPO\'s), where a controller\'s '
                  'relative %s at (N, β) is its %s divided by the three controllers\' mean %s there, so every '
                  '(N, β) weighs the same; agrees when g > 0' % (m, m, m, m), 'g')
        if not cells:
            c.missing = 'no valid step_down groups of all three controllers in the time-varying sweep'
            out.append(c)
            continue

        def g_of(v, m=m):
            rel = {ctl: 0.0 for ctl in PAPER}
            for n, b in cells:
                mean = sum(at(v, x, n, b, m) for x in PAPER) / 3.0
                for ctl in PAPER:
                    rel[ctl] += at(v, ctl, n, b, m) / mean / len(cells)
            return min(rel['crw'], rel['dpo']) - rel['gp_dpo']
        decide(c, per_draw(draws, used, g_of), '>', 0.0, used, draws)
        margin_sensitivity(c, 'threshold of g')
        measured = measured_values(draws, used)
        c.evidence = 'mean relative %s over %d (N, β): %s' % (m, len(cells), ', '.join(
            '%s %.3f' % (label(ctl), sum(at(measured, ctl, n, b, m) / (sum(at(measured, x, n, b, m) for x in PAPER)
                                                                       / 3.0) for n, b in cells) / len(cells))
            for ctl in PAPER))
        out.append(c)
    for tag, m in (('e3', 'R'), ('e4', 'A')):
        c = Claim(tag, 'Under V2, every controller becomes more %s (lower %s) as β grows' % (
            'reactive' if m == 'R' else 'adaptive', m),
            'ρ = the largest, over controllers, of the mean over N of Spearman\'s rank correlation of %s with β '
            '(ties share their mean rank); agrees when ρ < 0' % m, 'ρ')
        if not cells:
            c.missing = 'no valid step_down groups of all three controllers in the time-varying sweep'
            out.append(c)
            continue
        sizes = sorted({n for n, _ in cells})

        def rho_of(v, m=m, per=False):
            rhos = {}
            for ctl in PAPER:
                values = [spearman([b for nn, b in cells if nn == n], [at(v, ctl, n, b, m) for nn, b in cells if nn == n])
                          for n in sizes]
                values = [x for x in values if not math.isnan(x)]
                rhos[ctl] = sum(values) / len(values) if values else float('nan')
            return rhos if per else max(rhos.values())
        decide(c, per_draw(draws, used, rho_of), '<', 0.0, used, draws)
        margin_sensitivity(c, 'threshold of ρ', '%+.2f')
        measured = rho_of(measured_values(draws, used), per=True)
        c.evidence = 'mean ρ: ' + ', '.join('%s %+.2f' % (label(ctl), r) for ctl, r in measured.items())
        out.append(c)
    return out


def evaluate(ideal, tv, label, z_below=Z_BELOW):
    """Every claim, in the paper's order, from the ideal sweep folders and the time-varying one; z_below:
    claim (b)'s "first negative Z" on the Z scale of the tables' definitions."""
    draws = read_draws(list(ideal) + ([tv] if tv else []))
    missing = [f for f, d in draws.items() if d is None]
    draws = {f: d for f, d in draws.items() if d is not None}
    out = claim_a(draws, label) + claim_b(draws, label, z_below) + claim_c(draws, label) + claim_d(draws, label) + \
        claim_e(draws, label, tv if tv in draws else None)
    for c in out:
        if c.verdict == 'not measured' and missing and not c.missing:
            c.missing = 'no bootstrap in %s' % ', '.join(missing)
    return out, missing
