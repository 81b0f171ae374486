"""Figures of a robustness sweep (plot_sweep.py; docs/robustness-study.md): SAA robustness against the
noise level, PD robustness against the rate multiplier (per controller, one panel per N; the measure and its
normalised form; bands: 95 % confidence interval over the seeds' per-run values), and P(t) under population
dynamics with the active robot count beside it (read from the records' world/population)."""
import csv
import os
import textwrap
from collections import defaultdict

from swarm_forage.robustness import tables as rt

STYLES = ['-', '--', ':', '-.']
MARKERS = ['o', 's', '^', 'D', 'v']
TICKS_PER_SECOND = 5.0  # as plot_sweep.py's P(N, t): the paper's 5 ticks per simulated second


def _panels(plt, rows, sizes):
    fig, axes = plt.subplots(rows, len(sizes), figsize=(4.2 * len(sizes), 3.3 * rows), squeeze=False,
                             sharex=True)
    return fig, axes


def _band(ax, xs, spreads, colour, style, marker, label, normalized, floor=None):
    pts = sorted(zip(xs, spreads), key=lambda p: p[0])
    x = [p for p, _ in pts]
    m = [s.mean for _, s in pts]
    ax.plot(x, m, ls=style, marker=marker, color=colour, label=label)
    lo = [s.mean - s.ci95 if s.ci95 == s.ci95 else s.mean for _, s in pts]
    hi = [s.mean + s.ci95 if s.ci95 == s.ci95 else s.mean for _, s in pts]
    if normalized:  # the normalised forms are bounded: so are their bands
        lo, hi = [max(-1.0, v) for v in lo], [min(1.0, v) for v in hi]
    elif floor is not None:  # a distance is never below zero: neither is its band
        lo = [max(floor, v) for v in lo]
    ax.fill_between(x, lo, hi, color=colour, alpha=0.15, lw=0)


def _invalid_note(fig, points, width_inches):
    """Below the panels, wrapped to the figure's width: the settings without a value and why."""
    bad = [p for p in points if not p['valid']]
    if not bad:
        return
    reasons = sorted({p['status'] for p in bad})
    text = textwrap.fill('%d settings without a value: %s' % (len(bad), '; '.join(reasons)),
                         width=max(40, int(width_inches * 17)))
    lines = text.count('\n') + 1
    fig.subplots_adjust(bottom=fig.subplotpars.bottom + 0.035 * lines)
    fig.text(0.01, 0.005, text, fontsize=7, color='tab:red', va='bottom', ha='left')


def saa_figure(plt, points, out, arena, look):
    """SAA robustness against noise level: row 1 the DTW distance d (lower: closer to the noise-free run),
    row 2 sigma(-d) - sigma(d); the noise-free run is level 0 (d = 0) by definition."""
    pts = [p for p in points if p['measure'] == 'saa' and p['arena'] == arena]
    if not pts:
        return []
    sizes = sorted({p['N'] for p in pts})
    fig, axes = _panels(plt, 2, sizes)
    for col, n in enumerate(sizes):
        for c in look.in_order(p['controller'] for p in pts):
            mine = [p for p in pts if p['N'] == n and p['controller'] == c and p['valid']]
            if not mine:
                continue
            for row, (key, normalized) in enumerate((('per_run', False), ('per_run_normalized', True))):
                xs = [0.0] + [p['noise_level'] for p in mine]
                spreads = [rt.Spread([0.0])] + [p[key] for p in mine]
                _band(axes[row][col], xs, spreads, look.colour(c), '-', 'o', look.label(c), normalized, floor=0.0)
        axes[1][col].set_xlabel('noise level (sigma; misread probability)')
    return _finish(fig, axes, pts, sizes, arena, look, out, 'robustness_saa_%s.png' % arena,
                   'DTW distance d to noise-free P(t)\n(lower: more robust)',
                   'SAA robustness sigma(-d) - sigma(d)\n(higher: more robust)')


def _finish(fig, axes, pts, sizes, arena, look, out, name, top, bottom):
    """Titles, the settings without a value, labels, grid and legend of a two-row figure; saves it."""
    for col, n in enumerate(sizes):
        axes[0][col].set_title('N = %d, %s' % (n, arena))
    axes[0][0].set_ylabel(top)
    axes[1][0].set_ylabel(bottom)
    for ax in axes.flat:
        ax.grid(alpha=0.3)
    axes[0][0].legend(fontsize=6)
    fig.tight_layout()
    _invalid_note(fig, pts, fig.get_figwidth())
    return [look.save(fig, out, name)]


def pd_figure(plt, points, out, arena, look):
    """PD robustness against the rate multiplier (x1 = the experiment's base of each family): row 1 theta
    (blocks; 0 = as the queue predicts), row 2 sigma(theta) - sigma(-theta); one line style per family."""
    pts = [p for p in points if p['measure'] == 'pd' and p['arena'] == arena]
    if not pts:
        return []
    sizes = sorted({p['N'] for p in pts})
    families = sorted({p['family'] for p in pts}, key=lambda f: (-len(f), f))
    fig, axes = _panels(plt, 2, sizes)
    for col, n in enumerate(sizes):
        for c in look.in_order(p['controller'] for p in pts):
            for k, fam in enumerate(families):
                mine = [p for p in pts if p['N'] == n and p['controller'] == c and p['family'] == fam and p['valid']]
                if not mine:
                    continue
                for row, (key, normalized) in enumerate((('per_run', False), ('per_run_normalized', True))):
                    _band(axes[row][col], [p['multiplier'] for p in mine], [p[key] for p in mine], look.colour(c),
                          STYLES[k % len(STYLES)], MARKERS[k % len(MARKERS)],
                          '%s, %s' % (look.label(c), rt.family_name(fam)), normalized)
        axes[1][col].set_xlabel('rate multiplier\n(x1: the base of each family)')
        axes[1][col].set_xscale('log', base=2)
    return _finish(fig, axes, pts, sizes, arena, look, out, 'robustness_pd_%s.png' % arena,
                   'theta [blocks]\n(higher: more robust)', 'PD robustness sigma(theta) - sigma(-theta)')


def _record_words(folder):
    """key -> {word name: value} of the sweep's plan (runs.tsv: a record key, then its run_experiment words)."""
    words = {}
    try:
        with open(os.path.join(folder, 'runs.tsv')) as f:
            for line in f:
                parts = line.rstrip('\n').split('\t')
                words[parts[0]] = dict(w.split(':=', 1) for w in parts[1:] if ':=' in w)
    except OSError:
        pass
    return words


def _active_counts(folder, controller, n, rates, every):
    """[(tick, mean active over the records)] of the planned records of (controller, N, rates), one point
    every `every` ticks, from their world/population; and how many records were read."""
    import rosbag

    sums, count, records = defaultdict(float), defaultdict(int), 0
    for key, w in sorted(_record_words(folder).items()):
        if w.get('controller') != controller or int(w.get('n_robots', -1)) != n:
            continue
        if any(abs(float(w.get('population/' + r, 0)) - rates[r]) > 1e-12 * max(1.0, rates[r]) for r in rt.RATES):
            continue
        path = os.path.join(folder, 'runs', key + '.bag')
        if not os.path.isfile(path):
            continue
        with rosbag.Bag(path) as bag:
            for _, msg, _ in bag.read_messages(topics=['/world/population']):
                if msg.tick % every == 0:
                    sums[msg.tick] += msg.active
                    count[msg.tick] += 1
        records += 1
    return [(t, sums[t] / count[t]) for t in sorted(sums)], records


def population_figure(plt, folder, points, series, out, arena, look):
    """P(t) under the strongest population dynamics of the sweep (the largest family at its largest
    multiplier) against its reference, with the active robot count beside it, one row per N."""
    pts = [p for p in points if p['measure'] == 'pd' and p['arena'] == arena]
    if not pts:
        return []
    fam = max({p['family'] for p in pts}, key=lambda f: (len(f), f))
    top = max(p['multiplier'] for p in pts if p['family'] == fam)
    chosen = [p for p in pts if p['family'] == fam and p['multiplier'] == top]
    sizes = sorted({p['N'] for p in chosen})
    by_identity = defaultdict(list)
    for r in series:
        by_identity[r['identity']].append(r)
    fig, axes = plt.subplots(len(sizes), 2, figsize=(11, 3.3 * len(sizes)), squeeze=False)
    ticks = max(p['T'] for p in chosen) or 1
    every = max(1, int(ticks // 400))
    for row, n in enumerate(sizes):
        left, right = axes[row]
        order = look.in_order(p['controller'] for p in chosen)
        for p in sorted((p for p in chosen if p['N'] == n), key=lambda p: order.index(p['controller'])):
            colour = look.colour(p['controller'])
            for ident, style, what in ((p['identity'], '-', 'x%g' % top), (p['reference'], '--', 'reference')):
                s = sorted(by_identity.get(ident, []), key=lambda r: int(r['sample']))
                if s:
                    left.plot([(int(r['tick_end']) + 1) / TICKS_PER_SECOND for r in s],
                              [float(r['P_mean']) for r in s], ls=style, color=colour,
                              label='%s, %s' % (look.label(p['controller']), what))
            active, records = _active_counts(folder, p['controller'], n, p['rates'], every)
            if active:
                right.plot([t / TICKS_PER_SECOND for t, _ in active], [a for _, a in active], color=colour,
                           label='%s (%d runs)' % (look.label(p['controller']), records))
        rates = ', '.join('%s %g' % (r, chosen[0]['rates'][r]) for r in rt.RATES if chosen[0]['rates'][r])
        left.set_title('P(t), N = %d, %s: %s x%g (%s /tick)' % (n, arena, rt.family_name(fam), top, rates),
                       fontsize=8)
        left.set_ylabel('blocks collected P(N, t)')
        right.set_title('active robots, N = %d (%s x%g)' % (n, rt.family_name(fam), top), fontsize=8)
        right.set_ylabel('active robots (mean over runs)')
        right.set_ylim(bottom=0)
        for ax in (left, right):
            ax.set_xlabel('simulated time [s]')
            ax.grid(alpha=0.3)
            if ax.get_legend_handles_labels()[0]:
                ax.legend(fontsize=6)
            else:
                look.missing(ax, 'no world/population in the records' if ax is right else 'no series')
    fig.tight_layout()
    return [look.save(fig, out, 'population_%s.png' % arena)]


def read_series(folder):
    with open(os.path.join(folder, 'tables', 'series.csv')) as f:
        return list(csv.DictReader(f))


def figures(plt, folder, out, look):
    """Every robustness figure of one sweep folder (none when it has no robustness table)."""
    points = rt.read(folder)
    files = []
    for arena in sorted({p['arena'] for p in points}):
        files += saa_figure(plt, points, out, arena, look)
        files += pd_figure(plt, points, out, arena, look)
        files += population_figure(plt, folder, points, read_series(folder), out, arena, look)
    return files
