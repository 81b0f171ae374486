"""Recorded runs and a sweep's tables, read one way for every script (summarize_run.py, plot_sweep.py,
paper_report.py, plot_metrics.py, sweep.records).

A run's samples and the ticks they count come from the C++ `read_run`, which counts a bag exactly as
metrics_node counts a replay of it (core RunFollower and interval accumulator); this module reads from
the bag only what is not counted: the run's parameters, how it ended, the nest, caches, the condition
and the last arena snapshot. Needs the sourced workspace (rosbag, rosrun).
"""
import csv
import math
import os
import subprocess

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


class Sample:
    """One sample as metrics_node publishes it (metrics/performance, its ~csv)."""

    __slots__ = ("run", "swarm_size", "tick_end", "interval_ticks", "P", "p", "n_ca", "s", "final")

    def __init__(self, row):
        for name in ("run", "swarm_size", "tick_end", "interval_ticks", "P", "p"):
            setattr(self, name, int(row[name]))
        self.n_ca, self.s = float(row["n_ca"]), float(row["s"])
        self.final = row["final"].strip() in ("1", "true", "True")


class Tick:
    """One tick as counted: world/performance joined with its swarm/status ranges."""

    __slots__ = ("tick", "delivered", "cumulative", "in_avoidance", "covered", "ranges", "throttle", "last")

    def __init__(self, row):
        for name in ("tick", "delivered", "cumulative", "in_avoidance", "covered", "ranges"):
            setattr(self, name, int(row[name]))
        self.throttle = float(row["throttle"])
        self.last = row["last"] == "1"


def series(path, interval, ticks=False):
    """(samples, ticks, notes) of the run in the bag at `path`, cut at `interval` ticks per sample, as
    metrics_node counts a replay of it (`read_run`); a run cut short ends with a short, non-final
    sample. `ticks` empty unless asked for; notes are read_run's warnings. Raises BagError."""
    cmd = ["rosrun", "swarm_forage", "read_run", path, "sample_interval:=%d" % interval]
    if ticks:
        cmd.append("ticks:=true")
    try:
        proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, universal_newlines=True)
    except OSError as e:
        raise BagError("cannot run read_run (source the workspace's devel/setup.bash): %s" % e)
    notes = [line.replace("read_run: ", "", 1) for line in proc.stderr.splitlines() if line.strip()]
    if proc.returncode != 0:
        raise BagError("; ".join(notes) or "read_run exited %d" % proc.returncode)
    parts = proc.stdout.split("\n\n")
    samples = [Sample(r) for r in csv.DictReader(parts[0].splitlines())]
    counted = [Tick(r) for r in csv.DictReader(parts[1].splitlines())] if ticks and len(parts) > 1 else []
    return samples, counted, notes


class Run:
    """One recorded run: what its bag says besides the counted series (samples, ticks: see series())."""

    def __init__(self, path):
        self.path = path
        self.reindexed = False
        self.topics = {}  # key of TOPICS -> the bag's topic
        self.types_by_topic = {}
        self.run_info = None
        self.run_end = None
        self.nest = None
        self.caches = []  # world/caches messages, in tick order
        self.controllers = set()  # of the first tick's swarm/status
        self.throttle_n = 0
        self.throttle_min = math.inf
        self.throttle_max = -math.inf
        self.throttle_first = None
        self.robots_n = 0
        self.blocks_n = 0
        self.robots_last = None
        self.blocks_last = None
        self.first_stamp = None  # (tick, stamp seconds) of a message after tick 0, without run_info
        self.samples, self.ticks, self.notes = [], [], []


def read_run(path, interval=1000, ticks=True):
    """The run recorded at `path`, with its series (see series()); raises BagError when the bag cannot be
    read. A bag its writer never closed is read from a reindexed temporary copy (the original is left)."""
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
        tmp = _reindexed_copy(rosbag, path)
        bag = rosbag.Bag(tmp, "r")
    except Exception as e:  # ROSBagException, ROSBagFormatException, OSError, struct.error, ...
        raise BagError("%s: %s" % (type(e).__name__, e))
    run = Run(path)
    run.reindexed = tmp is not None
    try:
        with bag:
            _read_messages(bag, run)
        run.samples, run.ticks, run.notes = series(tmp or path, interval, ticks)
    except BagError:
        raise
    except Exception as e:  # a corrupt chunk, a bad message definition, a truncated record
        raise BagError("%s: %s" % (type(e).__name__, e))
    finally:
        if tmp is not None:
            os.unlink(tmp)
    return run


def _read_messages(bag, run):
    run.types_by_topic = {t: v.msg_type for t, v in bag.get_type_and_topic_info().topics.items()}
    run.topics = chosen = choose_topics(run.types_by_topic)

    def messages(key, raw=False):
        return bag.read_messages(topics=[chosen[key]], raw=raw) if key in chosen else []

    for _, msg, _ in messages("run_info"):
        if run.run_info is None:
            run.run_info = msg
    for _, msg, _ in messages("nest"):
        run.nest = msg
    for _, msg, _ in messages("run_end"):
        run.run_end = msg
    run.caches = [msg for _, msg, _ in messages("caches")]  # recorded when the cache changes: a few
    for _, msg, _ in messages("throttle"):  # recorded at tick 0 and when V changes
        run.throttle_n += 1
        run.throttle_min = min(run.throttle_min, msg.value)
        run.throttle_max = max(run.throttle_max, msg.value)
        if run.throttle_first is None:
            run.throttle_first = msg
    first = None
    for _, msg, _ in messages("status"):  # the controllers: the first tick's answers
        if first is not None and msg.tick != first:
            break
        first = msg.tick
        run.controllers.add(msg.controller)
    if run.run_info is None:  # the pace, from the stamps
        for key in ("performance", "status"):
            for _, msg, _ in messages(key):
                if msg.tick > 0 and msg.header.stamp.to_sec() > 0:
                    run.first_stamp = (msg.tick, msg.header.stamp.to_sec())
                    break
            if run.first_stamp:
                break
    # Snapshots are large: keep the last one raw and deserialize only that.
    for key in ("robots", "blocks"):
        last, n = None, 0
        for _, raw, _ in messages(key, raw=True):
            last, n = raw, n + 1
        setattr(run, key + "_n", n)
        setattr(run, key + "_last", _deserialize(last))


def _reindexed_copy(rosbag, path):
    """Path of a reindexed temporary copy of the unindexed bag at path."""
    import shutil
    import tempfile

    fd, tmp = tempfile.mkstemp(suffix=".bag", prefix="swarm_forage_run_")
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


def ticks_per_second(run):
    """(ticks per second, where it comes from) of a Run."""
    if run.run_info is not None and run.run_info.ticks_per_second > 0:
        return run.run_info.ticks_per_second, "run_info"
    if run.first_stamp is not None:
        tick, stamp = run.first_stamp
        return tick / stamp, "message stamps"
    return 5.0, "default (no run_info, no stamps)"


# A sweep's tables (run_tables, metrics/compute): scalability, self_organization, flexibility, series.

class TableMissing(Exception):
    pass


def table(path):
    """The rows of one table CSV as dicts; raises TableMissing when there is no such file."""
    if not os.path.isfile(path):
        raise TableMissing(path)
    with open(path) as f:
        return list(csv.DictReader(f))


def sweep_table(folder, name):
    """The rows of table `name` of a sweep output folder (FOLDER/tables/NAME.csv)."""
    return table(os.path.join(folder, "tables", name + ".csv"))


def ideal(row):
    """Whether a table row is of the ideal condition (V = 0)."""
    return row["waveform"] == "null"


def final_samples(series_rows):
    """(arena, controller, N) -> the last sample (series.csv row) of each ideal group."""
    last = {}
    for r in series_rows:
        if not ideal(r):
            continue
        key = (r["arena"], r["controller"], int(r["swarm_size"]))
        if key not in last or int(r["sample"]) > int(last[key]["sample"]):
            last[key] = r
    return last


# A sweep's record as `sweep` verifies it (sweep.records.verify).

RECORD_TOPICS = ("/world/run_info", "/world/provenance", "/world/run_end", "/world/performance")


def record_contents(path):
    """({topic: message count} of RECORD_TOPICS, {topic: last message} of run_info, provenance and run_end)
    of the bag at `path`; raises BagError ("Type: detail") when it cannot be read."""
    import rosbag

    try:
        # skip_index, then the index records of only the chunks that hold the three messages: rosbag reads every
        # chunk's index on open, about 20 times as long for a 50,000-tick record, and a sweep verifies serially.
        with rosbag.Bag(path, skip_index=True) as bag:
            counts = {t: bag.get_message_count(t) for t in RECORD_TOPICS}  # from the chunk infos
            wanted = {c.id for c in bag._connections.values() if c.topic in RECORD_TOPICS[:3]}
            for chunk in bag._chunks:
                if wanted.isdisjoint(chunk.connection_counts):
                    continue
                bag._file.seek(chunk.pos)
                rosbag.bag._skip_record(bag._file)
                bag._curr_chunk_info = chunk
                for _ in range(len(chunk.connection_counts)):
                    conn, index = bag._reader.read_connection_index_record()
                    if conn in wanted:
                        bag._connection_indexes[conn].extend(index)
            bag._connection_indexes_read = True  # else read_messages reads them all
            msgs = {t: m for t, m, _ in bag.read_messages(topics=list(RECORD_TOPICS[:3]))}
    except Exception as err:  # rosbag raises several kinds (unindexed, format, bz2, struct)
        raise BagError("%s: %s" % (type(err).__name__, str(err).strip() or "no detail"))
    return counts, msgs

