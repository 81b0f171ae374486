"""Drawing shared by the scripts' figures: a recorded run's arena (summarize_run.py's panel (c),
plot_sweep.py's --snapshot, the paper's Figure 1); values with their intervals (plot_sweep.py)."""
from collections import OrderedDict


def missing(ax, text):
    """An empty panel saying what it lacks."""
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, color="tab:red")
    ax.set_xticks([])
    ax.set_yticks([])


def draw_arena(ax, run, tps):
    """The last arena snapshot of a runs.Run: arena, nest and lights, free blocks, robots (carrying or not)."""
    from matplotlib.patches import Rectangle

    ri, nest, robots, blocks = run.run_info, run.nest, run.robots_last, run.blocks_last
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if ri is None and nest is None and robots is None and blocks is None:
        ax.set_title("(c) arena")
        missing(ax, "no run_info, nest, robots or blocks in the bag")
        return
    notes = []
    if ri is not None:
        ax.add_patch(Rectangle((0, 0), ri.arena_x, ri.arena_y, fill=False, edgecolor="black", lw=1.5))
        ax.set_xlim(-0.02 * ri.arena_x, 1.02 * ri.arena_x)
        ax.set_ylim(-0.02 * ri.arena_y, 1.02 * ri.arena_y)
    else:
        notes.append("no run_info: arena bounds unknown")
    if nest is not None:
        ax.add_patch(Rectangle((nest.center_x - nest.size_x / 2, nest.center_y - nest.size_y / 2), nest.size_x,
                               nest.size_y, facecolor="tab:green", alpha=0.2, edgecolor="tab:green", label="nest"))
        if nest.light_x:
            ax.scatter(nest.light_x, nest.light_y, marker="*", s=160, color="gold", edgecolors="black",
                       linewidths=0.6, zorder=4, label="lights")
    else:
        notes.append("no /world/nest")
    if blocks is not None:
        free = [i for i in range(len(blocks.x)) if i >= len(blocks.carrier) or blocks.carrier[i] < 0]
        ax.scatter([blocks.x[i] for i in free], [blocks.y[i] for i in free], marker="s", s=9, color="saddlebrown",
                   zorder=2, label="blocks (%d free)" % len(free))
    else:
        notes.append("no /world/blocks")
    tick = None
    if robots is not None and len(robots.x):
        n = len(robots.x)
        carrying = [i for i in range(n) if i < len(robots.carried_block) and robots.carried_block[i] >= 0]
        cset = set(carrying)
        idle = [i for i in range(n) if i not in cset]
        size = max(0.3, min(12.0, 4000.0 / n))
        ax.scatter([robots.x[i] for i in idle], [robots.y[i] for i in idle], s=size, color="tab:blue",
                   linewidths=0, zorder=3, label="robots (%d)" % len(idle))
        ax.scatter([robots.x[i] for i in carrying], [robots.y[i] for i in carrying], s=size * 1.5,
                   color="tab:red", linewidths=0, zorder=3, label="carrying (%d)" % len(carrying))
        tick = robots.tick
    else:
        notes.append("no /world/robots")
    when = " at t = %.1f s (tick %d)" % (tick / tps, tick) if tick is not None else ""
    ax.set_title("(c) arena snapshot%s" % when)
    if ax.get_legend_handles_labels()[0]:
        legend = ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), ncol=5, fontsize=8)
        for handle in getattr(legend, "legend_handles", None) or legend.legendHandles:
            if hasattr(handle, "set_sizes"):  # dots of a large swarm are too small to see in the legend
                handle.set_sizes([max(handle.get_sizes()[0], 20.0)] if len(handle.get_sizes()) else [20.0])
    if notes:
        ax.text(0.01, 0.99, "; ".join(notes), ha="left", va="top", transform=ax.transAxes, color="tab:red",
                fontsize=8)


def dodge(k, count, log=True, step=0.06):
    """The x offset of the k-th of `count` series at one x, so their error bars stand side by side: a factor
    2^(step * offset) on a log axis, an added step * offset (in x units) on a linear one."""
    offset = k - (count - 1) / 2.0
    return (lambda x: x * 2 ** (step * offset)) if log else (lambda x: x + step * offset)


def interval_line(ax, xs, points, color, label, names, marker="o", ls="-"):
    """A line through the points (intervals.Interval) at xs, each point's interval as an error bar from
    lo to hi; a point without one drawn hollow. Returns [(label, name, note)] of the points without one
    (names: each point's x as words, e.g. its N)."""
    ax.plot(xs, [p.estimate for p in points], marker=marker, ls=ls, color=color, label=label, markersize=5)
    bars = [(x, p) for x, p in zip(xs, points) if p.drawn]
    if bars:
        ax.errorbar([x for x, _ in bars], [(p.lo + p.hi) / 2 for _, p in bars],
                    yerr=[(p.hi - p.lo) / 2 for _, p in bars], fmt="none", ecolor=color, capsize=3, lw=1)
    bare = [(x, p) for x, p in zip(xs, points) if not p.drawn]
    if bare:
        ax.plot([x for x, _ in bare], [p.estimate for _, p in bare], marker=marker, ls="none", color=color,
                markerfacecolor="white", markersize=6, zorder=3)
    return [(label, name, p.note) for name, p in zip(names, points) if not p.drawn]


def notes_text(notes, total, axis="N"):
    """The words saying which points have no interval and why ("no interval: 1 seed: CRW at N = 4, 8"), or
    the one reason when none of the `total` points has one; '' when every point has one."""
    by = OrderedDict()
    for label, name, note in notes:
        by.setdefault(note, OrderedDict()).setdefault(label, []).append(name)
    if notes and len(notes) == total and len(by) == 1:
        return "no interval at any point (%s): means without their spread" % next(iter(by)).replace(
            "no interval: ", "")
    lines = []
    for note, who in by.items():
        parts = ["%s at %s = %s" % (label, axis, ", ".join(names)) for label, names in who.items()]
        text = "%s: %s" % (note, "; ".join(parts))
        lines += [text] if len(text) <= 100 else ["%s:" % note] + ["  " + p for p in parts]
    return "\n".join(lines)


def interval_notes(ax, notes, total, axis="N", y=-0.17):
    """notes_text under the axes, in red."""
    text = notes_text(notes, total, axis)
    if text:
        ax.text(0.0, y, text, ha="left", va="top", transform=ax.transAxes, color="tab:red", fontsize=7)
