"""Shared helpers for the rostest nodes: collect a run's messages, open a bag once it is closed, write and
remove what a test makes."""
import glob
import os
import time

import rosbag
import rospy
from swarm_forage.msg import IntervalPerformance, Performance
from tmp_files import removed_at_exit, write  # noqa: F401 (the graph tests take them from here)


# How long a wait may see no progress at all (no new message) before it fails: far above the slowest pause
# seen on a loaded 2-core machine. A wait is bounded by progress, never by the time a whole run takes.
QUIET = 300.0


def until(done, progress, what, quiet=QUIET):
    """Waits until done() is true; fails naming `what` when progress() (a count that grows while the run
    moves on) has not changed for `quiet` seconds."""
    last, since = progress(), time.time()
    while not done():
        if rospy.is_shutdown():
            raise AssertionError('shut down while waiting for ' + what)
        now = progress()
        if now != last:
            last, since = now, time.time()
        elif time.time() - since > quiet:
            raise AssertionError('%s: nothing moved on for %.0f s (at %s)' % (what, quiet, now))
        time.sleep(0.05)


class RunCollector:
    """Collects world/performance (per tick) and metrics/performance (per interval) by run."""

    def __init__(self, performance_topic='world/performance', metrics_topic='metrics/performance'):
        """performance_topic None: metrics only. A test must not subscribe to what `rosbag play
        --wait-for-subscribers` publishes, or the bag may start before the node under test listens."""
        self.ticks = {}      # run -> list of Performance
        self.intervals = {}  # run -> list of IntervalPerformance
        self.subs = [rospy.Subscriber(metrics_topic, IntervalPerformance, self._on_interval, queue_size=10000)]
        if performance_topic:
            self.subs.append(rospy.Subscriber(performance_topic, Performance, self._on_perf, queue_size=100000,
                                              tcp_nodelay=True))

    def _on_perf(self, msg):
        self.ticks.setdefault(msg.run, []).append(msg)

    def _on_interval(self, msg):
        self.intervals.setdefault(msg.run, []).append(msg)

    def _moved(self):
        return sum(map(len, self.intervals.values())) + sum(map(len, self.ticks.values()))

    def wait_final(self, run, timeout=QUIET):
        """Waits for the final metrics sample of `run` while messages keep coming (`timeout`: the longest
        pause without one); returns its interval list."""
        until(lambda: self.intervals.get(run) and self.intervals[run][-1].final, self._moved,
              'the final metrics/performance of run %d' % run, max(timeout, QUIET))
        return self.intervals[run]

    def wait_ticks(self, run, count, timeout=QUIET):
        """The first `count` world/performance messages of `run`. Another topic's final message (the
        metrics) can arrive before the world's last ticks do: wait for them rather than read too early."""
        try:
            until(lambda: len(self.ticks.get(run, [])) >= count, self._moved, '%d ticks of run %d' % (count, run),
                  max(timeout, QUIET))
        except AssertionError:
            pass  # the caller compares what came
        return self.ticks.get(run, [])[:count]


class LiveThrottle:
    """For a unittest.TestCase whose `throttle` list collects environment/throttle: waiting on a live run."""

    def wait_for(self, what, predicate, timeout=QUIET):
        """Waits while the run moves on: any message the test collects (its list attributes) is progress."""
        until(predicate, lambda: sum(len(v) for v in vars(self).values() if isinstance(v, list)), what,
              max(timeout, QUIET))

    def throttle_after(self, tick):
        self.wait_for('a throttle after tick %d' % tick, lambda: self.throttle and self.throttle[-1].tick > tick)
        return self.throttle[-1]


def open_bag(path, timeout=QUIET):
    """Opens a bag for reading, waiting until its writer has closed it while its files grow."""
    def size():
        return sum(os.path.getsize(p) for p in glob.glob(glob.escape(path) + '*') if os.path.isfile(p))
    last, since = size(), time.time()
    while True:
        try:
            return rosbag.Bag(path)
        except Exception as err:  # still being written, or not there yet
            now = size()
            if now != last:
                last, since = now, time.time()
            elif time.time() - since > max(timeout, QUIET):
                raise AssertionError('bag %s not readable, and not growing for %.0f s: %s' % (path, timeout, err))
            time.sleep(0.2)


def series(intervals):
    """The comparable content of a metrics/performance series."""
    return [(m.tick_end, m.interval_ticks, m.P, m.p, m.n_ca, m.final, m.swarm_size) for m in intervals]
