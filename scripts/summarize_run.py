#!/usr/bin/env python3
"""Summarize one run bag written by world_node (or run_experiment).

    summarize_run.py BAG [--interval TICKS] [--csv METRICS_CSV] [--plot OUT.png]

Reads the bag with the rosbag Python API. Messages are deserialized with classes generated from the
definitions stored in the bag, so the swarm_forage Python message modules are not needed.

Prints the run's parameters (world/run_info), ticks recorded, simulated time, blocks delivered, the
mean interference (robots in collision avoidance per tick, summed over the controller ranges of
swarm/status) and a per-interval table of P (cumulative blocks at the interval's end), p (blocks
delivered in the interval) and n_ca (mean robots in collision avoidance per tick in the interval);
intervals are counted from the first recorded tick exactly as metrics_node does. With --csv, also
prints the table metrics_node wrote live and checks it against the bag. With --plot, writes one PNG:
(a) P over simulated time with p per interval, (b) interference, (c) the last arena snapshot.

A topic missing from the bag (a run cut short) is reported and the rest is summarized. A bag that
cannot be read is one error line and exit status 2.
"""
import argparse
import csv
import math
import os
import sys

PROG = os.path.basename(sys.argv[0])

# key: (topic as recorded by world_node, message type)
TOPICS = {
    "run_info": ("/world/run_info", "swarm_forage/RunInfo"),
    "nest": ("/world/nest", "swarm_forage/Nest"),
    "run_end": ("/world/run_end", "swarm_forage/RunEnd"),
    "performance": ("/world/performance", "swarm_forage/Performance"),
    "status": ("/swarm/status", "swarm_forage/SwarmStatus"),
    "throttle": ("/environment/throttle", "swarm_forage/Throttle"),
    "robots": ("/world/robots", "swarm_forage/RobotStateArray"),
    "blocks": ("/world/blocks", "swarm_forage/BlockArray"),
    "caches": ("/world/caches", "swarm_forage/CacheArray"),
}


class BagError(Exception):
    pass


def choose_topics(types_by_topic):
    """Maps each key of TOPICS to the bag topic holding it: the usual name, else any topic of that type
    (a remapped or namespaced recording)."""
    chosen = {}
    for key, (topic, msg_type) in TOPICS.items():
        if types_by_topic.get(topic) == msg_type:
            chosen[key] = topic
            continue
        others = sorted(t for t, ty in types_by_topic.items() if ty == msg_type)
        if others:
            chosen[key] = others[0]
    return chosen


class Run:
    """Everything summarize_run needs from one bag, reduced while reading."""

    def __init__(self):
        self.run_info = None
        self.run_end = None
        self.nest = None
        self.run_id = None
        self.other_runs = set()
        self.perf_ticks = []  # one entry per world/performance message, in tick order
        self.perf_delivered = []
        self.perf_cumulative = []
        self.perf_last = False
        self.swarm_size = None
        self.status = {}  # tick -> {first_id: (count, in_avoidance)}
        self.controllers = set()
        self.throttle_n = 0
        self.throttle_min = math.inf
        self.throttle_max = -math.inf
        self.throttle_first = None
        self.robots_n = 0
        self.blocks_n = 0
        self.robots_last = None
        self.blocks_last = None
        self.caches = []  # world/caches messages, in tick order
        self.first_stamp = None  # (tick, stamp seconds) of a performance message, for ticks/s


def _accept_run(run, msg_run):
    """True when a message of run `msg_run` belongs to the run being summarized."""
    if run.run_id is None:
        run.run_id = msg_run
    if msg_run != run.run_id:
        run.other_runs.add(msg_run)
        return False
    return True


def read_bag(path):
    """Reads the bag at path into a Run and the topic map; raises BagError when it cannot be read."""
    try:
        import rosbag
    except ImportError as e:
        raise BagError("the rosbag Python module is not available (%s); run with PATH=/usr/bin:$PATH" % e)
    if not os.path.exists(path):
        raise BagError("no such file")
    if not os.path.isfile(path):
        raise BagError("not a file")
    tmp = None
    try:
        bag = rosbag.Bag(path, "r")
    except rosbag.ROSBagUnindexedException:
        # Written by a recorder that never closed it (a run cut short): reindex a temporary copy.
        tmp = _reindexed_copy(rosbag, path)
        bag = rosbag.Bag(tmp, "r")
    except Exception as e:  # ROSBagException, ROSBagFormatException, OSError, struct.error, ...
        raise BagError("%s: %s" % (type(e).__name__, e))

    run = Run()
    run.reindexed = tmp is not None
    try:
        with bag:
            info = bag.get_type_and_topic_info()
            types_by_topic = {t: v.msg_type for t, v in info.topics.items()}
            chosen = choose_topics(types_by_topic)
            by_topic = {topic: key for key, topic in chosen.items()}
            # RunInfo first: it names the run whose messages are summarized.
            if "run_info" in chosen:
                for _, msg, _ in bag.read_messages(topics=[chosen["run_info"]]):
                    if run.run_info is None:
                        run.run_info = msg
                        run.run_id = msg.run
            if "nest" in chosen:
                for _, msg, _ in bag.read_messages(topics=[chosen["nest"]]):
                    run.nest = msg
            if "run_end" in chosen:
                for _, msg, _ in bag.read_messages(topics=[chosen["run_end"]]):
                    run.run_end = msg
            if "caches" in chosen:  # recorded when the cache changes: a few messages
                run.caches = [msg for _, msg, _ in bag.read_messages(topics=[chosen["caches"]])]
            # Snapshots are large: keep the last one raw and deserialize only that.
            heavy = [chosen[k] for k in ("robots", "blocks") if k in chosen]
            light = [chosen[k] for k in ("performance", "status", "throttle") if k in chosen]
            if light:
                for topic, msg, _ in bag.read_messages(topics=light):
                    _add_message(run, by_topic[topic], msg)
            if heavy:
                for topic, raw, _ in bag.read_messages(topics=heavy, raw=True):
                    key = by_topic[topic]
                    if key == "robots":
                        run.robots_n += 1
                        run.robots_last = raw
                    else:
                        run.blocks_n += 1
                        run.blocks_last = raw
            run.robots_last = _deserialize(run.robots_last)
            run.blocks_last = _deserialize(run.blocks_last)
    except BagError:
        raise
    except Exception as e:  # a corrupt chunk, a bad message definition, a truncated record
        raise BagError("%s: %s" % (type(e).__name__, e))
    finally:
        if tmp is not None:
            os.unlink(tmp)
    return run, chosen, types_by_topic


def _reindexed_copy(rosbag, path):
    """Path of a reindexed temporary copy of the unindexed bag at path (the original is left alone)."""
    import shutil
    import tempfile

    fd, tmp = tempfile.mkstemp(suffix=".bag", prefix="summarize_run_")
    os.close(fd)
    try:
        shutil.copyfile(path, tmp)
        with rosbag.Bag(tmp, "a", allow_unindexed=True) as b:
            for _ in b.reindex():
                pass
        return tmp
    except Exception as e:
        os.unlink(tmp)
        raise BagError("unindexed bag (not closed by its writer) that cannot be reindexed: %s: %s"
                       % (type(e).__name__, e))


def _deserialize(raw):
    if raw is None:
        return None
    _datatype, data, _md5, _pos, pytype = raw
    msg = pytype()
    msg.deserialize(data)
    return msg


def _add_message(run, key, msg):
    if key == "performance":
        if not _accept_run(run, msg.run):
            return
        if run.perf_ticks and msg.tick <= run.perf_ticks[-1]:
            return  # a duplicate (or a tick of an earlier reset): count each tick once
        run.perf_ticks.append(msg.tick)
        run.perf_delivered.append(msg.delivered)
        run.perf_cumulative.append(msg.cumulative)
        run.perf_last = bool(msg.last)
        run.swarm_size = msg.swarm_size
        if run.first_stamp is None and msg.tick > 0 and msg.header.stamp.to_sec() > 0:
            run.first_stamp = (msg.tick, msg.header.stamp.to_sec())
    elif key == "status":
        if not _accept_run(run, msg.run):
            return
        ranges = run.status.setdefault(msg.tick, {})
        if msg.first_id not in ranges:  # a range reported twice for a tick counts once
            ranges[msg.first_id] = (msg.count, msg.in_avoidance)
        run.controllers.add(msg.controller)
        if run.first_stamp is None and msg.tick > 0 and msg.header.stamp.to_sec() > 0:
            run.first_stamp = (msg.tick, msg.header.stamp.to_sec())
        if run.swarm_size is None:
            run.swarm_size = msg.swarm_size
    elif key == "throttle":
        run.throttle_n += 1
        run.throttle_min = min(run.throttle_min, msg.value)
        run.throttle_max = max(run.throttle_max, msg.value)
        if run.throttle_first is None:
            run.throttle_first = msg


def interference_per_tick(run, ticks):
    """Robots in collision avoidance for each tick (0 where no status arrived, as metrics_node counts)."""
    return [sum(ia for _, ia in run.status.get(t, {}).values()) for t in ticks]


def intervals(ticks, delivered, cumulative, interference, interval):
    """The samples of metrics_node's IntervalAccumulator: (tick_end, n, P, p, n_ca); the last may be short."""
    out = []
    n = p = ia = 0
    for i, t in enumerate(ticks):
        n += 1
        p += delivered[i] if delivered is not None else 0
        ia += interference[i] if interference is not None else 0
        if n == interval or i == len(ticks) - 1:
            out.append(
                (
                    t,
                    n,
                    cumulative[i] if cumulative is not None else None,
                    p if delivered is not None else None,
                    ia / n if interference is not None else None,
                )
            )
            n = p = ia = 0
    return out


def ticks_per_second(run):
    if run.run_info is not None and run.run_info.ticks_per_second > 0:
        return run.run_info.ticks_per_second, "run_info"
    if run.first_stamp is not None:
        tick, stamp = run.first_stamp
        return tick / stamp, "message stamps"
    return 5.0, "default (no run_info, no stamps)"


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
        run, chosen, types_by_topic = read_bag(path)
    except BagError as e:
        print("%s: cannot read bag '%s': %s" % (PROG, path, e), file=sys.stderr)
        return 2

    missing = [TOPICS[k][0] for k in TOPICS if k not in chosen]
    ri = run.run_info
    tps, tps_source = ticks_per_second(run)

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
        print("  robots:             %s" % (run.swarm_size if run.swarm_size is not None else "unknown"))
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
    if run.other_runs:
        print("  note:               the bag also holds run(s) %s; only run %s is summarized"
              % (", ".join(str(r) for r in sorted(run.other_runs)), run.run_id))

    ticks = run.perf_ticks
    have_perf = bool(ticks)
    have_status = bool(run.status)
    if not have_perf and have_status:
        ticks = sorted(run.status)  # interference alone
    planned = " of %d planned" % ri.ticks if ri is not None else ""
    if have_perf:
        complete = "" if run.perf_last else ", no final tick: the run was cut short"
        print("  ticks recorded:     %d (%d..%d%s%s)" % (len(ticks), ticks[0], ticks[-1], planned, complete))
        print("  simulated time:     %.1f s (%g ticks/s, %s)" % (len(ticks) / tps, tps, tps_source))
        print("  blocks delivered:   %d" % run.perf_cumulative[-1])
    else:
        print("  ticks recorded:     0 world/performance messages%s" % planned)
        if ticks:
            print("  simulated time:     %.1f s of swarm/status (%g ticks/s, %s)" % (len(ticks) / tps, tps, tps_source))
        print("  blocks delivered:   n/a (no world/performance)")

    interference = interference_per_tick(run, ticks) if have_status else None
    if interference:
        mean = sum(interference) / len(interference)
        print("  mean interference:  %.3f robots in collision avoidance per tick" % mean)
        ranges = max(len(r) for r in run.status.values())
        size = run.swarm_size or (ri.swarm_size if ri is not None else None)
        incomplete = sum(
            1 for t in ticks if size is None or sum(c for c, _ in run.status.get(t, {}).values()) != size
        )
        note = "complete for every tick" if incomplete == 0 else "%d tick(s) with robots unreported" % incomplete
        print("  controller ranges:  %d (%s; status %s)" % (ranges, ", ".join(sorted(run.controllers)), note))
    else:
        print("  mean interference:  n/a (no swarm/status)")
    if run.throttle_first is not None:
        th = run.throttle_first
        print(
            "  environment:        %s (beta %g, alpha %g s), V in [%g, %g] over %d ticks"
            % (th.waveform, th.amplitude, th.alpha, run.throttle_min, run.throttle_max, run.throttle_n)
        )
    if run.robots_last is not None or run.blocks_last is not None:
        last = max(m.tick for m in (run.robots_last, run.blocks_last) if m is not None)
        print("  snapshots:          %d robots, %d blocks (last at tick %d)" % (run.robots_n, run.blocks_n, last))
    if missing:
        print("  missing topics:     %s" % ", ".join(missing))
    extra = sorted(t for t in types_by_topic if t not in chosen.values())
    if extra:
        print("  other topics:       %s" % ", ".join(extra))

    samples = []
    if ticks:
        samples = intervals(
            ticks,
            run.perf_delivered if have_perf else None,
            run.perf_cumulative if have_perf else None,
            interference,
            args.interval,
        )
        print("")
        print("per interval (%d ticks, from the bag):" % args.interval)
        print_table(samples, tps)

    status = 0
    if args.csv:
        try:
            rows = read_csv(args.csv)
        except ValueError as e:
            print("%s: %s" % (PROG, e), file=sys.stderr)
            status = 1
        else:
            print("")
            print("live metrics (%s):" % args.csv)
            print("  %4s %9s %7s %10s %8s %7s %10s %5s" % ("run", "tick_end", "ticks", "t [s]", "P", "p", "n_ca", "final"))
            for r in rows:
                print(
                    "  %4d %9d %7d %10.1f %8d %7d %10.3f %5s"
                    % (r["run"], r["tick_end"], r["interval_ticks"], (r["tick_end"] + 1) / tps, r["P"], r["p"],
                       r["n_ca"], "yes" if r["final"] else "")
                )
            print("  " + compare(rows, samples, run.run_id, args.interval))

    if args.plot:
        try:
            plot(args.plot, run, ticks, interference, samples, tps, args.interval)
            print("")
            print("plot: %s" % args.plot)
        except Exception as e:  # a plot failure must not hide the summary
            print("%s: cannot write plot '%s': %s: %s" % (PROG, args.plot, type(e).__name__, e), file=sys.stderr)
            status = 1
    if not ticks and run.run_info is None and run.robots_last is None:
        print("%s: nothing to summarize in '%s' (no swarm_forage run topics)" % (PROG, path), file=sys.stderr)
        status = status or 1
    if end is None or not end.complete:
        why = "no world/run_end" if end is None else "stopped at tick %d of %d (%s)" % (end.ticks_done, end.ticks,
                                                                                     end.reason)
        print("%s: the run in '%s' is incomplete: %s" % (PROG, path, why), file=sys.stderr)
        status = status or 1
    return status


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


def plot(out, run, ticks, interference, samples, tps, interval):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.patches import Rectangle

    ri = run.run_info
    n_robots = ri.swarm_size if ri is not None else run.swarm_size
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
    if run.perf_ticks:
        t = [(k + 1) / tps for k in run.perf_ticks]
        ax_p.plot(t, run.perf_cumulative, color="tab:blue", lw=1.5, label="P (cumulative, per tick)")
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
        t = [(k + 1) / tps for k in ticks]
        ax_i.plot(t, interference, color="tab:gray", lw=0.5, alpha=0.45, label="per tick")
        xs, ys = [], []
        for tick_end, n, _, _, n_ca in samples:
            xs += [(tick_end + 1 - n) / tps, (tick_end + 1) / tps]
            ys += [n_ca, n_ca]
        ax_i.plot(xs, ys, color="tab:red", lw=2, label="n_ca (mean per interval)")
        ax_i.legend(loc="upper left", fontsize=8)
    else:
        _missing(ax_i, "no /swarm/status in the bag")

    # (c) arena snapshot
    _snapshot(ax_s, run, tps, Rectangle)

    fig.tight_layout(rect=(0, 0, 1, 0.97))
    fig.savefig(out, dpi=110)
    plt.close(fig)


def _missing(ax, text):
    ax.text(0.5, 0.5, text, ha="center", va="center", transform=ax.transAxes, color="tab:red")
    ax.set_xticks([])
    ax.set_yticks([])


def _snapshot(ax, run, tps, Rectangle):
    ri, nest, robots, blocks = run.run_info, run.nest, run.robots_last, run.blocks_last
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    if ri is None and nest is None and robots is None and blocks is None:
        ax.set_title("(c) arena")
        _missing(ax, "no run_info, nest, robots or blocks in the bag")
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


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter,
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


if __name__ == "__main__":
    sys.exit(main())
