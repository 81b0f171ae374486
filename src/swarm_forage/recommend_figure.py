"""The figure of `recommend`: (left) every candidate's final P against its flexibility, the Pareto front
marked and the top choice labelled; (right) P(N) measured, with intervals, and the fitted curves with R^2."""
import os

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = {'crw': 'tab:blue', 'dpo': 'tab:orange', 'gp_dpo': 'tab:green'}
OTHERS = ['tab:red', 'tab:purple', 'tab:brown', 'tab:pink', 'tab:olive', 'tab:cyan']


def flexibility_score(d, weights):
    """The flexibility of a candidate in [0, 1] (1 most flexible): the mean of its normalised R and A scores,
    weighted as the target weighs them (equally when it weighs neither); None without R and A."""
    if d['R'] is None or d['A'] is None:
        return None
    wr, wa = weights.get('reactivity', 0.0), weights.get('adaptability', 0.0)
    sr, sa = d.get('s_reactivity'), d.get('s_adaptability')
    if sr is None or sa is None or wr + wa == 0:
        return None
    return (wr * sr + wa * sa) / (wr + wa)


def pareto(points):
    """The points (x, y, ...) no other point beats on both x and y (both higher-better)."""
    return [p for p in points if not any(q[0] >= p[0] and q[1] >= p[1] and (q[0], q[1]) != (p[0], p[1])
                                         for q in points)]


def draw(path, ranked, fits, library, t, weights):
    fig, (left, right) = plt.subplots(1, 2, figsize=(13, 5.2))
    pts = [(flexibility_score(d, weights), d['P'], d) for d in ranked]
    pts = [p for p in pts if p[0] is not None and p[1] is not None]
    names = sorted({d['controller'] for d in ranked})
    colours = {c: COLOURS.get(c) or OTHERS[k % len(OTHERS)] for k, c in enumerate(names)}
    if pts:
        for c in sorted(colours):
            mine = [p for p in pts if p[2]['controller'] == c]
            for fitted in (False, True):
                sel = [p for p in mine if (p[2]['source'] != 'measured') == fitted]
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
        left.set_xlabel('flexibility (normalised R and A, 1 = most reactive/adaptive)')
    else:
        left.text(0.5, 0.5, 'no R and A (conditions ideal or not weighted)', ha='center', transform=left.transAxes)
    left.set_ylabel('final P (blocks)')
    left.set_title('%s: performance against flexibility' % t['arena'])
    left.legend(fontsize=8, handlelength=3)
    for c, f in sorted(fits.items()):
        sizes = library.sizes(t['arena'], c)
        gs = [library.groups[(t['arena'], c, n, 'null', 0.0)] for n in sizes]
        lo = [g['P'] - g['lo'] if g['lo'] is not None else 0 for g in gs]
        hi = [g['hi'] - g['P'] if g['hi'] is not None else 0 for g in gs]
        right.errorbar(sizes, [g['P'] for g in gs], yerr=[lo, hi], fmt='o', color=colours.get(c), capsize=3,
                       label='%s measured (95%% interval)' % c)
        if f is not None:
            top_n = max(t['robots'], sizes[-1])
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
