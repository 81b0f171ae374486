"""The figure of `recommend`: (left) every candidate's final P against its flexibility, the Pareto front
marked and the top choice labelled; (right) P(N) measured, with intervals, and the fitted curves with R^2."""
import os

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {'crw': 'tab:blue', 'dpo': 'tab:orange', 'gp_dpo': 'tab:green'}
OTHERS = ['tab:red', 'tab:purple', 'tab:brown', 'tab:pink', 'tab:olive', 'tab:cyan']


def flexibility_scores(ranked, weights):
    """{id(candidate): flexibility in [0, 1]} (1 most flexible): the min-max scores of R/P and A/P across the
    candidates (lower is better), weighted as the target weighs reactivity and adaptability (equally when it
    weighs neither); candidates without R and A are left out."""
    wr, wa = weights.get('reactivity', 0.0), weights.get('adaptability', 0.0)
    wr, wa = (1.0, 1.0) if wr + wa == 0 else (wr, wa)
    have = [d for d in ranked if d['R/P'] is not None and d['A/P'] is not None]
    out = {id(d): 0.0 for d in have}
    for field, w in (('R/P', wr), ('A/P', wa)):
        vals = [d[field] for d in have]
        if not vals:
            continue
        best, worst = min(vals), max(vals)
        for d in have:
            s = 1.0 if best == worst else (worst - d[field]) / (worst - best)
            out[id(d)] += w * s / (wr + wa)
    return out


def pareto(points):
    """The points (x, y, ...) no other point beats on both x and y (both higher-better)."""
    return [p for p in points if not any(q[0] >= p[0] and q[1] >= p[1] and (q[0], q[1]) != (p[0], p[1])
                                         for q in points)]


def draw(path, ranked, fits, library, t, weights):
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 5.2))
    flex = flexibility_scores(ranked, weights)
    pts = [(flex[id(d)], d['P'], d) for d in ranked if id(d) in flex and d['P'] is not None]
    names = sorted({d['controller'] for d in ranked})
    colours = {c: COLOURS.get(c) or OTHERS[k % len(OTHERS)] for k, c in enumerate(names)}
    if pts:
        for c in sorted(colours):
            mine = [p for p in pts if p[2]['controller'] == c]
            for fitted in (False, True):
                sel = [p for p in mine if (p[2]['source'] != 'measured') == fitted]
                if not sel:
                    continue
                left.scatter([p[0] for p in sel], [p[1] for p in sel], marker='o', s=30, zorder=3,
                             label='%s %s' % (c, 'fitted P' if fitted else 'measured'), edgecolors=colours[c],
                             facecolors='none' if fitted else colours[c])
            for x, y, d in mine:
                left.annotate(str(d['N']), (x, y), fontsize=7, xytext=(3, 2), textcoords='offset points')
        front = sorted(pareto(pts), key=lambda p: p[0])
        left.plot([p[0] for p in front], [p[1] for p in front], 'k--', lw=1, label='Pareto front', zorder=2)
        top = ranked[0]
        mark = [p for p in pts if p[2] is top]
        if mark:
            left.scatter([mark[0][0]], [mark[0][1]], s=220, facecolors='none', edgecolors='red', lw=2, zorder=4,
                         label='top choice')
            left.annotate('%s N=%d' % (top['controller'], top['N']), (mark[0][0], mark[0][1]), color='red',
                          xytext=(8, -14), textcoords='offset points', fontsize=9, weight='bold')
        left.set_xlabel('flexibility (min-max of R/P and A/P, 1 = most reactive/adaptive)')
        left.legend(fontsize=8, handlelength=3)
    else:
        left.text(0.5, 0.5, 'no R and A (ideal conditions, or not measured)', ha='center', transform=left.transAxes)
    left.set_ylabel('final P (blocks)')
    left.set_title('%s: performance against flexibility' % t['arena'])
    for c, f in sorted(fits.items()):
        sizes = library.sizes(t['arena'], c)
        gs = [library.groups[(t['arena'], c, n, 'null', 0.0)] for n in sizes]
        lo = [g['P'] - g['lo'] if g['lo'] is not None else 0 for g in gs]
        hi = [g['hi'] - g['P'] if g['hi'] is not None else 0 for g in gs]
        right.errorbar(sizes, [g['P'] for g in gs], yerr=[lo, hi], fmt='o', color=colours.get(c), capsize=3,
                       label='%s measured (95%% interval)' % c)
        if f is not None:
            top_n = max(sizes[-1], min(t['robots'], 4 * sizes[-1]))  # as far as the fit stands in
            xs = [sizes[0] * (top_n / sizes[0]) ** (k / 200.0) for k in range(201)]
            right.plot(xs, [f(x) for x in xs], '-', color=colours.get(c), lw=1,
                       label='%s fit: b %.2f, c %.2g, R$^2$ %.3f' % (c, f.b, f.c, f.r2))
    right.axvline(t['robots'], color='grey', ls=':', lw=1, label='robots available (%d)' % t['robots'])
    right.set_xscale('log', base=2)
    right.set_xlabel('N')
    right.set_ylabel('final P (blocks), ideal')
    right.set_title('P(N) in %s: measured and fitted a N$^b$ e$^{cN}$' % t['arena'])
    right.legend(fontsize=7, handlelength=3)
    fig.tight_layout()
    folder = os.path.dirname(os.path.abspath(path))
    os.makedirs(folder, exist_ok=True)
    tmp = os.path.join(folder, '.%s.%d.png' % (os.path.basename(path), os.getpid()))
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    os.replace(tmp, path)
