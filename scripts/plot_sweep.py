#!/usr/bin/env python3
"""Figures of one or more sweeps (the tables `sweep` writes into DIR/tables):

    plot_sweep.py DIR [DIR ...] --output FIGDIR [--snapshot RUN.bag]

Into FIGDIR/<sweep folder name>/, per arena: P(N,t) per controller with 95 % CI bands, final P vs N (log2 N axis), e vs N and Z vs N;
for sweeps with time-varying conditions, R and A vs beta per N and waveform; for robustness sweeps (noise,
population dynamics) SAA robustness vs noise level, PD robustness vs rate multiplier and P(t) with the
active count (swarm_forage.robustness_figures; the other figures then show the plain runs only).
--snapshot draws the arena of a recorded run (nest, lights, blocks, cache, robots; the paper's Figure 1).
Prints each file.
"""
import argparse
import os
import sys
import types
from collections import defaultdict

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
from swarm_forage import runs  # noqa: E402
from swarm_forage.figures import draw_arena, missing  # noqa: E402
from swarm_forage import experiment  # noqa: E402
from swarm_forage import robustness_figures  # noqa: E402
from swarm_forage import robustness_tables  # noqa: E402


# Each controller's look, built-in or plugin, from the registry's listing (run_experiment --controllers).
def colour(c):
    return experiment.controller_kind(c)['colour']


def label(c):
    return experiment.controller_kind(c)['display_name']


def in_order(names):
    """The controllers among `names` in the listing's order; any it lacks (an old record's) last."""
    order = list(experiment.controller_names())
    return sorted(set(names), key=lambda c: (order.index(c) if c in order else len(order), c))


def rows(folder, name):
    try:
        return runs.sweep_table(folder, name)
    except runs.TableMissing as e:
        sys.exit('plot_sweep: %s missing (run the sweep to its end first)' % e)


def save(fig, out, name):
    path = os.path.join(out, name)
    fig.savefig(path, dpi=110, bbox_inches='tight')
    plt.close(fig)
    print(path)
    return path


def performance_figures(series, out, arena):
    by = defaultdict(list)  # (controller, N) -> samples of the ideal group
    for r in series:
        if r['arena'] == arena and runs.ideal(r):  # (plain runs only: see main)
            by[(r['controller'], int(r['swarm_size']))].append(r)
    controllers = in_order(k[0] for k in by)
    if not controllers:
        return []
    files = []
    fig, axes = plt.subplots(1, len(controllers), figsize=(5 * len(controllers), 4), sharey=True, squeeze=False)
    for ax, c in zip(axes[0], controllers):
        sizes = sorted(n for (cc, n) in by if cc == c)
        cmap = plt.get_cmap('viridis')
        for k, n in enumerate(sizes):
            s = sorted(by[(c, n)], key=lambda r: int(r['sample']))
            t = [(int(r['tick_end']) + 1) / 5.0 for r in s]  # the sample's end: its last tick + 1, 5 ticks/s
            m = [float(r['P_mean']) for r in s]
            ci = [float(r['P_ci95']) for r in s]
            color = cmap(k / max(1, len(sizes) - 1))
            ax.plot(t, m, color=color, label='N=%d' % n)
            ax.fill_between(t, [a - b for a, b in zip(m, ci)], [a + b for a, b in zip(m, ci)], color=color, alpha=0.15)
        ax.set_title('%s, %s' % (label(c), arena))
        ax.set_xlabel('simulated time [s]')
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2)
    axes[0][0].set_ylabel('blocks collected P(N, t)')
    files.append(save(fig, out, 'performance_%s.png' % arena))

    finals = runs.final_samples(series)
    fig, ax = plt.subplots(figsize=(6, 4))
    for c in controllers:
        pts = sorted((n, float(last['P_mean']), float(last['P_ci95'])) for (a, cc, n), last in finals.items()
                     if a == arena and cc == c)
        ns, m, ci = [p[0] for p in pts], [p[1] for p in pts], [p[2] for p in pts]
        ax.plot(ns, m, 'o-', color=colour(c), label=label(c))
        ax.fill_between(ns, [a - b for a, b in zip(m, ci)], [a + b for a, b in zip(m, ci)], color=colour(c), alpha=0.2)
    ax.set_xscale('log', base=2)
    ax.set_xlabel('swarm size N')
    ax.set_ylabel('final P (blocks at T), mean ± 95 % CI')
    ax.set_title('Performance at T, %s' % arena)
    ax.grid(alpha=0.3)
    ax.legend()
    files.append(save(fig, out, 'final_performance_%s.png' % arena))
    return files


def metric_figure(table, out, arena, size_key, value_key, ylabel, title, name, reference=None):
    pts = defaultdict(list)
    for r in table:
        if r['arena'] == arena and runs.ideal(r) and r['valid'] == '1':
            pts[r['controller']].append((int(r[size_key]), float(r[value_key])))
    if not pts:
        return []
    fig, ax = plt.subplots(figsize=(6, 4))
    for c in in_order(pts):
        if c in pts:
            p = sorted(pts[c])
            ax.plot([a for a, _ in p], [b for _, b in p], 'o-', color=colour(c), label=label(c))
    if reference is not None:
        ax.axhline(reference, color='grey', lw=0.8, ls='--')
    ax.set_xscale('log', base=2)
    ax.set_xlabel('swarm size N')
    ax.set_ylabel(ylabel)
    ax.set_title('%s, %s' % (title, arena))
    ax.grid(alpha=0.3)
    ax.legend()
    return [save(fig, out, name % arena)]


def flexibility_figure(table, out, arena):
    valid = [r for r in table if r['arena'] == arena and r['valid'] == '1']
    if not valid:
        return []
    waveforms = sorted({r['waveform'] for r in valid})
    sizes = sorted({int(r['N']) for r in valid})
    fig, axes = plt.subplots(2, len(waveforms), figsize=(5.5 * len(waveforms), 7), squeeze=False)
    styles = ['-', '--', ':', '-.']
    for col, w in enumerate(waveforms):
        for row, metric in enumerate(('R', 'A')):
            ax = axes[row][col]
            for c in in_order(r['controller'] for r in valid):
                for k, n in enumerate(sizes):
                    p = sorted((float(r['beta']), float(r[metric])) for r in valid
                               if r['waveform'] == w and r['controller'] == c and int(r['N']) == n)
                    if p:
                        ax.plot([a for a, _ in p], [b for _, b in p], marker='o', ls=styles[k % len(styles)],
                                color=colour(c), label='%s N=%d' % (label(c), n))
            ax.set_xlabel('beta')
            ax.set_ylabel({'R': 'reactivity R (lower: more reactive)', 'A': 'adaptability A (lower: more adaptive)'}[metric])
            ax.set_title('%s under %s, %s' % (metric, w, arena))
            ax.grid(alpha=0.3)
            ax.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    return [save(fig, out, 'flexibility_%s.png' % arena)]


def snapshot_figure(bag, out):
    from matplotlib.patches import Rectangle
    run = runs.read_run(bag, ticks=False)
    fig, ax = plt.subplots(figsize=(9, 5))
    draw_arena(ax, run, runs.ticks_per_second(run)[0])
    tick = run.robots_last.tick if run.robots_last is not None else None
    cache = ([c for c in run.caches if tick is None or c.tick <= tick] or [None])[-1]
    if cache is not None:
        for x, y, size, blocks in zip(cache.x, cache.y, cache.size, cache.blocks):
            ax.add_patch(Rectangle((x - size / 2, y - size / 2), size, size, facecolor='tab:purple', alpha=0.25,
                                   edgecolor='tab:purple', label='cache (%d blocks)' % blocks))
        ax.legend(loc='upper center', bbox_to_anchor=(0.5, -0.12), ncol=6, fontsize=8)
    ri = run.run_info
    if ri is not None:
        ax.set_title('%s, N = %d in %s, %s' % (label(ri.controller), ri.swarm_size, ri.arena,
                                                ax.get_title().replace('(c) arena snapshot ', '')))
    return [save(fig, out, 'arena_snapshot.png')]


def main(argv):
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='example:\n  plot_sweep.py results/sweeps/ideal_32x16 --output results/figures')
    ap.add_argument('sweeps', nargs='+', help='sweep output folders (with tables/)')
    ap.add_argument('--output', required=True, help='folder for the PNG files')
    ap.add_argument('--snapshot', help='a recorded run to draw as the arena figure (default: none)')
    a = ap.parse_args(argv)
    os.makedirs(a.output, exist_ok=True)
    files = []
    look = types.SimpleNamespace(colour=colour, label=label, in_order=in_order, save=save, missing=missing)
    for folder in a.sweeps:
        series, scal, selforg, flex = (rows(folder, n) for n in ('series', 'scalability', 'self_organization',
                                                                   'flexibility'))
        # Groups under noise or population dynamics have their own figures; the paper's show the plain runs.
        varied = robustness_tables.varied_identities(folder)
        series, scal, selforg, flex = ([r for r in t if r['identity'] not in varied]
                                       for t in (series, scal, selforg, flex))
        prefix = os.path.basename(os.path.normpath(folder))
        out = os.path.join(a.output, prefix)
        os.makedirs(out, exist_ok=True)
        for arena in sorted({r['arena'] for r in series}):
            files += performance_figures(series, out, arena)
            files += metric_figure(scal, out, arena, 'N2', 'e', 'Karp-Flatt e(N/2, N)', 'Scalability',
                                   'scalability_%s.png', reference=1.0)
            files += metric_figure(selforg, out, arena, 'm_i', 'Z_mean', 'self-organization Z (mean per sample)',
                                   'Self-organization', 'self_organization_%s.png', reference=0.5)
            files += flexibility_figure(flex, out, arena)
        if varied:
            files += robustness_figures.figures(plt, folder, out, look)
    if a.snapshot:
        files += snapshot_figure(a.snapshot, a.output)
    return 0 if files else 1


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
