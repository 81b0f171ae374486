"""Plots the tables metrics/compute wrote: e(N) and Z(N) per controller, R and A per condition.

    plot_metrics.py DIR [--output FILE.png]

DIR holds scalability.csv, self_organization.csv and flexibility.csv (the `output` of metrics/compute).
Only valid rows are plotted; the number of invalid rows is printed.
"""
import argparse
import os
import sys
from collections import defaultdict

import matplotlib
matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402
from swarm_forage.bags import runs  # noqa: E402


def read(directory, name):
    try:
        rows = runs.table(os.path.join(directory, name + '.csv'))
    except runs.TableMissing:
        sys.exit('%s: no %s.csv (call metrics/compute with output:=%s first)' % (directory, name, directory))
    valid = [r for r in rows if r['valid'] == '1']
    print('%s: %d rows, %d valid' % (name, len(rows), len(valid)))
    return valid


def curves(rows, size_key, value_key):
    """(controller, arena, environment) -> sorted [(N, value)]."""
    out = defaultdict(list)
    for r in rows:
        out[(r['controller'], r['arena'], r['environment'])].append((int(r[size_key]), float(r[value_key])))
    return {k: sorted(v) for k, v in out.items()}


def main(argv=None):
    ap = argparse.ArgumentParser(prog='plot_metrics.py', description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='example:\n  plot_metrics.py results/sweeps/ideal_32x16/tables --output e_z.png')
    ap.add_argument('directory', help='folder with scalability.csv, self_organization.csv and flexibility.csv')
    ap.add_argument('--output', default=None, help='PNG path (default: DIR/metrics.png)')
    args = ap.parse_args(argv)
    scal = read(args.directory, 'scalability')
    selforg = read(args.directory, 'self_organization')
    flex = read(args.directory, 'flexibility')

    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    for (controller, arena, env), pts in curves(scal, 'N2', 'e').items():
        axes[0].plot([n for n, _ in pts], [v for _, v in pts], 'o-', label='%s %s %s' % (controller, arena, env))
    axes[0].set(xscale='log', xlabel='swarm size N', ylabel='Karp-Flatt e', title='Scalability (lower is better)')
    for (controller, arena, env), pts in curves(selforg, 'm_i', 'Z_mean').items():
        axes[1].plot([n for n, _ in pts], [v for _, v in pts], 'o-', label='%s %s %s' % (controller, arena, env))
    axes[1].set(xscale='log', xlabel='swarm size N', ylabel='Z (mean over samples)', title='Self-organization')
    labels = ['%s N=%s\n%s' % (r['controller'], r['N'], r['environment']) for r in flex]
    xs = range(len(flex))
    axes[2].bar([x - 0.2 for x in xs], [float(r['R']) for r in flex], 0.4, label='R (reactivity)')
    axes[2].bar([x + 0.2 for x in xs], [float(r['A']) for r in flex], 0.4, label='A (adaptability)')
    axes[2].set_xticks(list(xs))
    axes[2].set_xticklabels(labels, fontsize=7)
    axes[2].set(ylabel='DTW distance', title='Flexibility (lower is better)')
    for ax in axes:
        if ax.get_legend_handles_labels()[0]:
            ax.legend(fontsize=7)
        ax.grid(alpha=0.3)
    fig.tight_layout()
    out = args.output or os.path.join(args.directory, 'metrics.png')
    fig.savefig(out, dpi=110)
    print('wrote', out)

