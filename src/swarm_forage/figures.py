"""Drawing shared by the scripts' figures: a recorded run's arena (summarize_run.py's panel (c),
plot_sweep.py's --snapshot, the paper's Figure 1)."""


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
