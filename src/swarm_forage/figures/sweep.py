"""Figures of one or more sweeps (the tables `sweep` writes into DIR/tables):

    plot_sweep.py DIR [DIR ...] --output FIGDIR [--snapshot RUN.bag]

Into FIGDIR/<sweep folder name>/, per arena: P(N,t) per controller with 95 % Student t bands over seeds
(clipped at 0: a count), final P vs N (log2 N axis), e vs N and Z vs N; for sweeps with time-varying
conditions, R and A vs beta per N and waveform (and the figures of their ideal groups say so); for
robustness sweeps (noise, population dynamics) SAA robustness vs noise level, PD robustness vs rate
multiplier and P(t) with the active count (swarm_forage.robustness.figures; the other figures then show
the plain runs only). Every point of final P, e, Z, R and A carries its 95 % bootstrap interval over seeds
(DIR/tables/bootstrap.csv; swarm_forage.study.intervals); a point without one (1 seed, no bootstrap.csv)
is drawn hollow and the figure says why. Legends state the seeds per group.
--snapshot draws the arena of a recorded run (nest, lights, blocks, cache, robots; the paper's Figure 1).
A sweep whose planned records are not all there (it has not finished) is refused (exit 1, saying how many
are missing) unless --partial is given; each of its figures then says it is partial.
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
from swarm_forage.bags import runs  # noqa: E402
from swarm_forage.experiment import kinds  # noqa: E402
from swarm_forage.figures.drawing import dodge, draw_arena, interval_line, interval_notes, missing, notes_text  # noqa
from swarm_forage.robustness import figures as robustness_figures  # noqa: E402
from swarm_forage.robustness import tables as robustness_tables  # noqa: E402
from swarm_forage.study import intervals  # noqa: E402
from swarm_forage.sweep import records  # noqa: E402

PARTIAL = {'note': None}  # the note every figure of a partial sweep carries


# Each controller's look, built-in or plugin, from the registry's listing (run_experiment --controllers).
def colour(c):
    return kinds.controller_kind(c)['colour']


label = kinds.display_name


def in_order(names):
    """The controllers among `names` in the listing's order; any it lacks (an old record's) last."""
    order = list(kinds.controller_names())
    return sorted(set(names), key=lambda c: (order.index(c) if c in order else len(order), c))


def rows(folder, name):
    try:
        return runs.sweep_table(folder, name)
    except runs.TableMissing as e:
        sys.exit('plot_sweep: %s missing (run the sweep to its end first)' % e)


def save(fig, out, name):
    if PARTIAL['note']:
        fig.text(0.5, 1.0, PARTIAL['note'], ha='center', va='bottom', color='tab:red', fontsize=9,
                 transform=fig.transFigure)
    path = os.path.join(out, name)
    fig.savefig(path, dpi=110, bbox_inches='tight')
    plt.close(fig)
    print(path)
    return path


class Sweep:
    """What every figure of one sweep folder shares: its bootstrap intervals and whether it has time-varying
    conditions (its figures of ideal groups then say so)."""

    def __init__(self, folder, series, flex, varied):
        self.intervals = intervals.SweepIntervals(folder, series, varied)
        self.time_varying = any(not runs.ideal(r) for r in series) or bool(flex)

    def title(self, title, arena):
        return '%s%s, %s' % (title, ' (ideal groups of the time-varying sweep)' if self.time_varying else '', arena)

    def caption(self, seeds, count=False):
        """The legend title: what the intervals are and how many seeds they come from."""
        if self.intervals.draws is not None:
            what = intervals.CAPTION
        elif count:
            what = intervals.T_CAPTION + ' (no bootstrap.csv)'
        else:
            what = 'no bootstrap.csv: no interval'
        return '%s\n%s' % (what, intervals.seeds_text(seeds))


def size_axis(ax, sizes):
    """A log2 axis of swarm size over the measured sizes and a margin (the side-by-side error bars fit)."""
    ax.set_xscale('log', base=2)
    if sizes:
        ax.set_xlim(min(sizes) / 1.5, max(sizes) * 1.5)
    ax.set_xlabel('swarm size N')


def performance_figures(series, out, arena, sweep):
    by = defaultdict(list)  # (controller, N) -> samples of the ideal group
    for r in series:
        if r['arena'] == arena and runs.ideal(r):  # (plain runs only: see main)
            by[(r['controller'], int(r['swarm_size']))].append(r)
    controllers = in_order(k[0] for k in by)
    if not controllers:
        return []
    files = []
    fig, axes = plt.subplots(1, len(controllers), figsize=(5 * len(controllers), 4), sharey=True, squeeze=False)
    seeds = []
    for ax, c in zip(axes[0], controllers):
        sizes = sorted(n for (cc, n) in by if cc == c)
        cmap = plt.get_cmap('viridis')
        notes = []
        for k, n in enumerate(sizes):
            s = sorted(by[(c, n)], key=lambda r: int(r['sample']))
            t = [(int(r['tick_end']) + 1) / 5.0 for r in s]  # the sample's end: its last tick + 1, 5 ticks/s
            m = [float(r['P_mean']) for r in s]
            count = int(s[-1]['runs'])
            seeds.append(count)
            bands = [intervals.count_band(a, float(r['P_ci95']), count) for a, r in zip(m, s)]
            color = cmap(k / max(1, len(sizes) - 1))
            ax.plot(t, m, color=color, label='N=%d' % n)
            if all(b is not None for b in bands):
                ax.fill_between(t, [b[0] for b in bands], [b[1] for b in bands], color=color, alpha=0.15)
            else:
                notes.append((label(c), str(n), intervals.seeds_note(count) if count < 2 else
                              'no interval: no finite P_ci95'))
        ax.set_title('%s, %s' % (label(c), arena))
        ax.set_xlabel('simulated time [s]')
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=2, loc='upper left')
        interval_notes(ax, notes, len(sizes))
    axes[0][0].set_ylabel('blocks collected P(N, t)')
    fig.suptitle('%s: mean with %s (%s)' % (sweep.title('P(N, t)', arena), intervals.T_CAPTION,
                                              intervals.seeds_text(seeds)), fontsize=9)
    files.append(save(fig, out, 'performance_%s.png' % arena))

    finals = runs.final_samples(series)
    fig, ax = plt.subplots(figsize=(6, 4))
    notes, seeds, total = [], [], 0
    for k, c in enumerate(controllers):
        pts = sorted((n, last) for (a, cc, n), last in finals.items() if a == arena and cc == c)
        points = []
        for n, last in pts:
            count, mean = int(last['runs']), float(last['P_mean'])
            if sweep.intervals.draws is not None:
                points.append(sweep.intervals.point(intervals.key(last, 'swarm_size'), 'P', mean, count,
                                                    count=True))
            else:  # no bootstrap: series.csv's Student t interval of the final sample, clipped at 0
                band = intervals.count_band(mean, float(last['P_ci95']), count)
                points.append(intervals.Interval(mean, *(band or (float('nan'),) * 2), count,
                                                       None if band else intervals.seeds_note(count)))
        seeds += [int(last['runs']) for _, last in pts]
        total += len(pts)
        shift = dodge(k, len(controllers))
        notes += interval_line(ax, [shift(n) for n, _ in pts], points, colour(c), label(c), [str(n) for n, _ in pts])
    size_axis(ax, [n for (a, _, n) in finals if a == arena])
    ax.set_ylabel('final P (blocks at T), mean and interval')
    ax.set_title(sweep.title('Performance at T', arena))
    ax.grid(alpha=0.3)
    ax.legend(title=sweep.caption(seeds, count=True), title_fontsize=7, fontsize=8)
    interval_notes(ax, notes, total)
    files.append(save(fig, out, 'final_performance_%s.png' % arena))
    return files


def metric_figure(table, out, arena, size_key, metric, value_key, ylabel, title, name, sweep, reference=None):
    pts = defaultdict(list)
    for r in table:
        if r['arena'] == arena and runs.ideal(r) and r['valid'] == '1':
            pts[r['controller']].append(r)
    if not pts:
        return []
    if metric == 'e':  # e(N1, N2): N1 the next smaller size, N/2 or N/4 as the sweep's sizes are
        ylabel = intervals.ratio_label((int(r['N1']), int(r['N2'])) for p in pts.values() for r in p)
    fig, ax = plt.subplots(figsize=(6, 4))
    controllers = [c for c in in_order(pts) if c in pts]
    notes, seeds = [], []
    for k, c in enumerate(controllers):
        p = sorted(pts[c], key=lambda r: int(r[size_key]))
        points = []
        for r in p:
            count = int(r['runs'])
            if metric == 'e':  # e depends on the N1 group's seeds too
                n1 = (arena, c, int(r['N1']), r['waveform'], float(r['beta']))
                count = min(count, sweep.intervals.seeds.get(n1, count))
            seeds.append(count)
            points.append(sweep.intervals.point(intervals.key(r, size_key), metric, float(r[value_key]), count))
        shift = dodge(k, len(controllers))
        notes += interval_line(ax, [shift(int(r[size_key])) for r in p], points, colour(c), label(c),
                               [r[size_key] for r in p])
    if reference is not None:
        ax.axhline(reference, color='grey', lw=0.8, ls='--')
    size_axis(ax, [int(r[size_key]) for p in pts.values() for r in p])
    ax.set_ylabel(ylabel)
    ax.set_title(sweep.title(title, arena))
    ax.grid(alpha=0.3)
    ax.legend(title=sweep.caption(seeds), title_fontsize=7, fontsize=8)
    interval_notes(ax, notes, len(seeds))
    return [save(fig, out, name % arena)]


MARKERS = ('o', 's', '^', 'D', 'v', 'P', 'X', '*')
STYLES = ('-', '--', ':', '-.')


def flexibility_figure(table, out, arena, sweep):
    valid = [r for r in table if r['arena'] == arena and r['valid'] == '1']
    if not valid:
        return []
    waveforms = sorted({r['waveform'] for r in valid})
    sizes = sorted({int(r['N']) for r in valid})
    controllers = in_order(r['controller'] for r in valid)
    betas = sorted({float(r['beta']) for r in valid})
    step = 0.01 * ((betas[-1] - betas[0]) or 1.0)
    fig, axes = plt.subplots(2, len(waveforms), figsize=(5.5 * len(waveforms), 7), squeeze=False)
    notes, seeds, total = [], [], 0
    for col, w in enumerate(waveforms):
        for row, metric in enumerate(('R', 'A')):
            ax = axes[row][col]
            series = [(c, n) for n in sizes for c in controllers]
            for k, (c, n) in enumerate(series):
                p = sorted((r for r in valid if r['waveform'] == w and r['controller'] == c and int(r['N']) == n),
                           key=lambda r: float(r['beta']))
                if not p:
                    continue
                points = [sweep.intervals.point(intervals.key(r, 'N'), metric, float(r[metric]), int(r['runs']))
                          for r in p]
                seeds += [int(r['runs']) for r in p]
                total += len(p)
                shift = dodge(k, len(series), log=False, step=step)
                i = sizes.index(n)
                notes += [('%s, %s: %s N=%d' % (metric, w, label(c), n), name, note) for _, name, note in
                          interval_line(ax, [shift(float(r['beta'])) for r in p], points, colour(c),
                                        '%s N=%d' % (label(c), n), [r['beta'] for r in p],
                                        marker=MARKERS[i % len(MARKERS)], ls=STYLES[i % len(STYLES)])]
            ax.set_xlabel('beta')
            ax.set_ylabel({'R': 'reactivity R (lower: more reactive)', 'A': 'adaptability A (lower: more adaptive)'}[metric])
            ax.set_title('%s under %s, %s' % (metric, w, arena))
            ax.grid(alpha=0.3)
    handles = {}
    for ax in axes.flat:  # one entry per (controller, N), in order: a column per N, a row per controller
        for h, text in zip(*ax.get_legend_handles_labels()):
            handles.setdefault(text, h)
    fig.tight_layout()
    fig.legend(list(handles.values()), list(handles), loc='center left', bbox_to_anchor=(1.0, 0.5), fontsize=8,
               handlelength=4, title=sweep.caption(seeds), title_fontsize=8)
    text = notes_text(notes, total, 'beta')
    if text:
        fig.text(0.0, 0.0, text, ha='left', va='top', color='tab:red', fontsize=7)
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


def main(argv=None):
    ap = argparse.ArgumentParser(prog='plot_sweep.py', description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='example:\n  plot_sweep.py results/sweeps/ideal_32x16 --output results/figures')
    ap.add_argument('sweeps', nargs='+', help='sweep output folders (with tables/)')
    ap.add_argument('--output', required=True,
                    help='folder for the PNG files: FIGDIR/<sweep folder name>/*.png, one subfolder per sweep')
    ap.add_argument('--snapshot', help='a recorded run to draw as the arena figure (default: none)')
    ap.add_argument('--partial', action='store_true', help='draw a sweep that has not finished (its figures say '
                    'so); without it such a sweep is refused')
    a = ap.parse_args(argv)
    unfinished = records.incomplete(a.sweeps)
    if unfinished and not a.partial:
        print('plot_sweep: the sweeps have not finished: %s; run them to their end, or give --partial to draw what '
              'there is' % '; '.join(unfinished), file=sys.stderr)
        return 1
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
        sweep = Sweep(folder, series, flex, varied)
        if sweep.intervals.missing:
            print('plot_sweep: %s; figures say so and draw no bootstrap intervals' % sweep.intervals.missing,
                  file=sys.stderr)
        lacking, planned = records.missing_records(folder)
        PARTIAL['note'] = ('PARTIAL: %d of %d planned records missing' % (lacking, planned)) if lacking else None
        prefix = os.path.basename(os.path.normpath(folder))
        out = os.path.join(a.output, prefix)
        os.makedirs(out, exist_ok=True)
        for arena in sorted({r['arena'] for r in series}):
            files += performance_figures(series, out, arena, sweep)
            files += metric_figure(scal, out, arena, 'N2', 'e', 'e', None, 'Scalability', 'scalability_%s.png',
                                   sweep, reference=1.0)
            files += metric_figure(selforg, out, arena, 'm_i', 'Z', 'Z_mean', 'self-organization Z (mean per sample)',
                                   'Self-organization', 'self_organization_%s.png', sweep, reference=0.5)
            files += flexibility_figure(flex, out, arena, sweep)
        if varied:
            files += robustness_figures.figures(plt, folder, out, look)
    PARTIAL['note'] = None
    if a.snapshot:
        files += snapshot_figure(a.snapshot, a.output)
    return 0 if files else 1


if __name__ == '__main__':  # paper runs it so, a process of its own
    sys.exit(main())
