"""Summarize one run bag written by world_node (or run_experiment).

    summarize_run.py BAG [--interval TICKS] [--csv METRICS_CSV] [--plot OUT.png]

Reads the run through swarm_forage.bags.runs: its samples and ticks are counted by the C++ read_run exactly as
metrics_node counts a replay of the bag; the rest (parameters, outcome, snapshots) is read with rosbag.

Prints the run's parameters (world/run_info), ticks recorded, simulated time, blocks delivered, the
mean interference (robots in collision avoidance per tick, summed over the controller ranges of
swarm/status) and a per-interval table of P (cumulative blocks at the interval's end), p (blocks
delivered in the interval) and n_ca (mean robots in collision avoidance per tick in the interval);
intervals are counted from the first recorded tick exactly as metrics_node does (a run cut short ends
with a short interval at its last recorded tick). With --csv, also
prints the table metrics_node wrote live and checks it against the bag. With --plot, writes one PNG:
(a) P over simulated time with p per interval, (b) interference, (c) the last arena snapshot.

A topic missing from the bag (a run cut short) is reported and the rest is summarized. A bag that
cannot be read is one error line and exit status 2.
"""
import argparse
import csv
import os
import sys

from swarm_forage.bags import runs
from swarm_forage.figures.drawing import draw_arena, missing as _missing

PROG = 'summarize_run.py'


def read_csv(path):
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        raise ValueError("cannot read %s: %s" % (path, e.strerror or e))
    need = ["run", "swarm_size", "tick_end", "interval_ticks", "P", "p", "n_ca", "final"]
    if not rows and os.path.getsize(path) == 0:
        raise ValueError("%s is empty (expected header %s)" % (path, ",".join(need)))
    with open(path, newline="") as f:
        header = next(csv.reader(f), [])
    missing = [c for c in need if c not in header]
    if missing:
        raise ValueError("%s lacks column(s) %s (expected header %s)" % (path, ", ".join(missing), ",".join(need)))
    out = []
    for lineno, row in enumerate(rows, start=2):
        try:
            out.append(
                {
                    "run": int(row["run"]),
                    "swarm_size": int(row["swarm_size"]),
                    "tick_end": int(row["tick_end"]),
                    "interval_ticks": int(row["interval_ticks"]),
                    "P": int(row["P"]),
                    "p": int(row["p"]),
                    "n_ca": float(row["n_ca"]),
                    "final": row["final"].strip() in ("1", "true", "True"),
                }
            )
        except (TypeError, ValueError):
            raise ValueError("%s line %d is malformed: %s" % (path, lineno, ",".join(str(v) for v in row.values())))
    return out


def fmt(v, spec):
    return ("%" + spec) % v if v is not None else "n/a".rjust(int(spec.split(".")[0].rstrip("dfs") or 0))


def print_table(samples, tps):
    print("  %9s %7s %10s %8s %7s %10s" % ("tick_end", "ticks", "t [s]", "P", "p", "n_ca"))
    for tick_end, n, P, p, n_ca in samples:
        print(
            "  %9d %7d %10.1f %8s %7s %10s"
            % (tick_end, n, (tick_end + 1) / tps, fmt(P, "8d"), fmt(p, "7d"), fmt(n_ca, "10.3f"))
        )


def summarize(path, args):
    try:
        run = runs.read_run(path, args.interval, ticks=True)
    except runs.BagError as e:
        print("%s: cannot read bag '%s': %s" % (PROG, path, e), file=sys.stderr)
        return 2

    ri = run.run_info
    tps, tps_source = runs.ticks_per_second(run)
    size = ri.swarm_size if ri is not None else (run.samples[-1].swarm_size if run.samples else None)
    run_id = ri.run if ri is not None else (run.samples[0].run if run.samples else None)
    print_run(path, run, size)
    ticks, interference = print_ticks(run, size, tps, tps_source)

    samples = [(x.tick_end, x.interval_ticks, x.P, x.p, x.n_ca) for x in run.samples]
    if samples:
        print("")
        print("per interval (%d ticks, from the bag):" % args.interval)
        print_table(samples, tps)

    status = 0
    if args.csv:
        status = print_live(args.csv, samples, run_id, args.interval, tps)
    if args.plot:
        try:
            plot(args.plot, run, interference, samples, tps, args.interval)
            print("")
            print("plot: %s" % args.plot)
        except Exception as e:  # a plot failure must not hide the summary
            print("%s: cannot write plot '%s': %s: %s" % (PROG, args.plot, type(e).__name__, e), file=sys.stderr)
            status = 1
    if not ticks and run.run_info is None and run.robots_last is None:
        print("%s: nothing to summarize in '%s' (no swarm_forage run topics)" % (PROG, path), file=sys.stderr)
        status = status or 1
    end = run.run_end
    if end is None or not end.complete:
        why = "no world/run_end" if end is None else "stopped at tick %d of %d (%s)" % (end.ticks_done, end.ticks,
                                                                                     end.reason)
        print("%s: the run in '%s' is incomplete: %s" % (PROG, path, why), file=sys.stderr)
        status = status or 1
    return status


def print_run(path, run, size):
    """What the run was (run_info, else what swarm/status tells) and how it ended."""
    ri = run.run_info
    print("run bag: %s" % path)
    if run.reindexed:
        print("  note:               the bag was not closed by its writer; read from a reindexed copy")
    if ri is not None:
        print("  controller:         %s" % ri.controller)
        print("  arena:              %s (%g x %g m), %d blocks" % (ri.arena, ri.arena_x, ri.arena_y, ri.n_blocks))
        print("  robots:             %d" % ri.swarm_size)
        print("  seed:               %d" % ri.seed)
        print("  run:                %d" % ri.run)
    else:
        if run.controllers:
            print("  controller:         %s (no run_info; from swarm/status)" % ", ".join(sorted(run.controllers)))
        else:
            print("  controller:         unknown (no run_info, no swarm/status)")
        print("  arena:              unknown (no run_info)")
        print("  robots:             %s" % (size if size is not None else "unknown"))
        print("  seed:               unknown (no run_info)")
    end = run.run_end
    if end is None:
        print("  outcome:            INCOMPLETE: no world/run_end (the recorder never closed the run: killed?)")
    elif end.complete:
        print("  outcome:            complete (%d of %d ticks)" % (end.ticks_done, end.ticks))
    else:
        print("  outcome:            INCOMPLETE: run %d stopped at tick %d of %d (%s)"
              % (end.run, end.ticks_done, end.ticks, end.reason))
    if ri is not None and ri.identity:
        print("  identity:           %s (%s, world: %s)" % (ri.identity, ri.mode, ri.world_constants))
    for note in run.notes:  # how read_run followed the run: joined late, ticks never whole, another run
        print("  note:               %s" % note)


def print_ticks(run, size, tps, tps_source):
    """The ticks recorded, blocks delivered, interference, the condition, the snapshots and the topics; returns
    (the ticks, the robots in collision avoidance per tick or None)."""
    ri = run.run_info
    chosen, types_by_topic = run.topics, run.types_by_topic
    missing = [runs.TOPICS[k][0] for k in runs.TOPICS if k not in chosen]
    ticks = [t.tick for t in run.ticks]
    planned = " of %d planned" % ri.ticks if ri is not None else ""
    if ticks:
        complete = "" if run.ticks[-1].last else ", no final tick: the run was cut short"
        print("  ticks recorded:     %d (%d..%d%s%s)" % (len(ticks), ticks[0], ticks[-1], planned, complete))
        print("  simulated time:     %.1f s (%g ticks/s, %s)" % (len(ticks) / tps, tps, tps_source))
        print("  blocks delivered:   %d" % run.ticks[-1].cumulative)
    else:
        print("  ticks recorded:     0 world/performance messages%s" % planned)
        print("  blocks delivered:   n/a (no world/performance)")

    interference = [t.in_avoidance for t in run.ticks] if "status" in chosen else None
    if interference:
        mean = sum(interference) / len(interference)
        print("  mean interference:  %.3f robots in collision avoidance per tick" % mean)
        ranges = max(t.ranges for t in run.ticks)
        incomplete = sum(1 for t in run.ticks if size is None or t.covered != size)
        note = "complete for every tick" if incomplete == 0 else "%d tick(s) with robots unreported" % incomplete
        print("  controller ranges:  %d (%s; status %s)" % (ranges, ", ".join(sorted(run.controllers)), note))
    elif interference is not None:
        print("  mean interference:  n/a (no tick counted: no world/performance)")
    else:
        print("  mean interference:  n/a (no swarm/status)")
    if run.throttle_first is not None:
        th = run.throttle_first
        # A bag recorded before targets and series has neither field: the paper's carry_speed.
        target = getattr(th, "target", "") or "carry_speed"
        what = ("series %s #%s" % (os.path.basename(th.series), th.series_digest[:8]) if th.waveform == "series"
                else "%s (beta %g, alpha %g s)" % (th.waveform, th.amplitude, th.alpha))
        print(
            "  environment:        %s on %s, V in [%g, %g] over %d ticks"
            % (what, target, run.throttle_min, run.throttle_max, run.throttle_n)
        )
    if run.robots_last is not None or run.blocks_last is not None:
        last = max(m.tick for m in (run.robots_last, run.blocks_last) if m is not None)
        print("  snapshots:          %d robots, %d blocks (last at tick %d)" % (run.robots_n, run.blocks_n, last))
    if missing:
        print("  missing topics:     %s" % ", ".join(missing))
    extra = sorted(t for t in types_by_topic if t not in chosen.values())
    if extra:
        print("  other topics:       %s" % ", ".join(extra))
    return ticks, interference


def print_live(path, samples, run_id, interval, tps):
    """The table metrics_node wrote live (--csv), checked against the bag's; 1 when it cannot be read."""
    try:
        rows = read_csv(path)
    except ValueError as e:
        print("%s: %s" % (PROG, e), file=sys.stderr)
        return 1
    print("")
    print("live metrics (%s):" % path)
    print("  %4s %9s %7s %10s %8s %7s %10s %5s" % ("run", "tick_end", "ticks", "t [s]", "P", "p", "n_ca", "final"))
    for r in rows:
        print(
            "  %4d %9d %7d %10.1f %8d %7d %10.3f %5s"
            % (r["run"], r["tick_end"], r["interval_ticks"], (r["tick_end"] + 1) / tps, r["P"], r["p"],
               r["n_ca"], "yes" if r["final"] else "")
        )
    print("  " + compare(rows, samples, run_id, interval))
    return 0


def compare(rows, samples, run_id, interval):
    """One line saying whether the live CSV agrees with the intervals computed from the bag."""
    if not samples:
        return "(nothing in the bag to compare with)"
    mine = [r for r in rows if run_id is None or r["run"] == run_id]
    if not mine:
        return "(no CSV rows for run %s)" % run_id
    if any(r["interval_ticks"] > interval for r in mine):
        return "(CSV sampled at a different interval than --interval %d; not compared)" % interval
    by_end = {s[0]: s for s in samples}
    diffs, matched = [], 0
    for r in mine:
        s = by_end.get(r["tick_end"])
        if s is None:
            continue
        matched += 1
        _, n, P, p, n_ca = s
        bad = []
        if n != r["interval_ticks"]:
            bad.append("ticks %d vs %d" % (r["interval_ticks"], n))
        if P is not None and P != r["P"]:
            bad.append("P %d vs %d" % (r["P"], P))
        if p is not None and p != r["p"]:
            bad.append("p %d vs %d" % (r["p"], p))
        if n_ca is not None and abs(n_ca - r["n_ca"]) > 1e-5 * max(1.0, abs(n_ca)):
            bad.append("n_ca %g vs %g" % (r["n_ca"], n_ca))
        if bad:
            diffs.append("tick_end %d: %s" % (r["tick_end"], ", ".join(bad)))
    if matched == 0:
        return "(no CSV interval ends at the same tick as the bag's)"
    if diffs:
        more = "" if len(diffs) <= 5 else "; ... %d more" % (len(diffs) - 5)
        return "live metrics DIFFER from the bag (CSV vs bag) at %s%s" % ("; ".join(diffs[:5]), more)
    return "live metrics agree with the bag on %d of %d interval(s)" % (matched, len(samples))


def plot(out, run, interference, samples, tps, interval):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ri = run.run_info
    n_robots = ri.swarm_size if ri is not None else (run.samples[-1].swarm_size if run.samples else None)
    title = "%s, N = %s, arena %s" % (
        ri.controller if ri is not None else "/".join(sorted(run.controllers)) or "controller unknown",
        n_robots if n_robots is not None else "?",
        ri.arena if ri is not None else "unknown",
    )
    fig, (ax_p, ax_i, ax_s) = plt.subplots(3, 1, figsize=(10, 13), gridspec_kw={"height_ratios": [1, 1, 1.35]})
    fig.suptitle(title, fontsize=13)

    # (a) performance
    ax_p.set_title("(a) blocks delivered")
    ax_p.set_xlabel("simulated time [s]")
    if run.ticks:
        t = [(k.tick + 1) / tps for k in run.ticks]
        ax_p.plot(t, [k.cumulative for k in run.ticks], color="tab:blue", lw=1.5, label="P (cumulative, per tick)")
        ax_p.set_ylabel("P (cumulative)", color="tab:blue")
        ax_bar = ax_p.twinx()
        ax_p.set_zorder(ax_bar.get_zorder() + 1)  # the P line above the bars
        ax_p.patch.set_visible(False)
        starts = [(s[0] + 1 - s[1]) / tps for s in samples]  # a bar spans its interval
        widths = [s[1] / tps for s in samples]
        ax_bar.bar(starts, [s[3] for s in samples], width=widths, align="edge", color="tab:orange", alpha=0.35,
                   edgecolor="white", label="p per interval (%d ticks)" % interval)
        ax_bar.set_ylabel("p per interval", color="tab:orange")
        h1, l1 = ax_p.get_legend_handles_labels()
        h2, l2 = ax_bar.get_legend_handles_labels()
        ax_p.legend(h1 + h2, l1 + l2, loc="upper left", fontsize=8)
    else:
        _missing(ax_p, "no /world/performance in the bag")

    # (b) interference
    ax_i.set_title("(b) interference: robots in collision avoidance")
    ax_i.set_xlabel("simulated time [s]")
    ax_i.set_ylabel("robots")
    if interference:
        t = [(k.tick + 1) / tps for k in run.ticks]
        ax_i.plot(t, interference, color="tab:gray", lw=0.5, alpha=0.45, label="per tick")
        xs, ys = [], []
        for tick_end, n, _, _, n_ca in samples:
            xs += [(tick_end + 1 - n) / tps, (tick_end + 1) / tps]
            ys += [n_ca, n_ca]
        ax_i.plot(xs, ys, color="tab:red", lw=2, label="n_ca (mean per interval)")
        handles, labels = ax_i.get_legend_handles_labels()
        if any(k.throttle != 0 for k in run.ticks):  # the condition V the world applied, e.g. a measured series
            ax_v = ax_i.twinx()
            ax_v.plot(t, [k.throttle for k in run.ticks], color="tab:purple", lw=1.2, label="V applied")
            ax_v.set_ylabel("V (condition)", color="tab:purple")
            ax_v.set_ylim(-1.05, 1.05)
            h, lab = ax_v.get_legend_handles_labels()
            handles, labels = handles + h, labels + lab
        ax_i.legend(handles, labels, loc="upper left", fontsize=8)
    else:
        _missing(ax_i, "no /swarm/status in the bag")

    # (c) arena snapshot
    draw_arena(ax_s, run, tps)

    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main(argv=None):
    parser = argparse.ArgumentParser(prog=PROG, description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter,
                                     epilog="example:\n  rosrun swarm_forage summarize_run.py results/demo.bag "
                                            "--csv results/demo_metrics.csv --plot results/demo.png")
    parser.add_argument("bag", help="run bag written by world_node or run_experiment")
    parser.add_argument("--interval", type=int, default=1000, help="sample interval in ticks (default 1000)")
    parser.add_argument("--csv", help="metrics CSV written by metrics_node (~csv) to print and check (default: none)")
    parser.add_argument("--plot", help="write a PNG with performance, interference and an arena snapshot (default: none)")
    args = parser.parse_args(argv)
    if args.interval < 1:
        parser.error("--interval must be >= 1 tick")
    return summarize(args.bag, args)

