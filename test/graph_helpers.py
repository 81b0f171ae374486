"""Shared helpers for the rostest nodes: collect a run's messages, open a bag once it is closed, write and
remove what a test makes."""
import atexit
import os
import shutil
import time

import rosbag
import rospy
from swarm_forage.msg import IntervalPerformance, Performance


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

    def wait_final(self, run, timeout):
        """Waits for the final metrics sample of `run`; returns its interval list."""
        deadline = time.time() + timeout
        while time.time() < deadline and not rospy.is_shutdown():
            samples = self.intervals.get(run, [])
            if samples and samples[-1].final:
                return samples
            time.sleep(0.05)
        raise AssertionError('no final metrics/performance for run %d within %.0f s (have %d samples, %d ticks)'
                             % (run, timeout, len(self.intervals.get(run, [])), len(self.ticks.get(run, []))))

    def wait_ticks(self, run, count, timeout):
        """The first `count` world/performance messages of `run`. Another topic's final message (the
        metrics) can arrive before the world's last ticks do: wait for them rather than read too early."""
        deadline = time.time() + timeout
        while len(self.ticks.get(run, [])) < count and time.time() < deadline and not rospy.is_shutdown():
            time.sleep(0.05)
        return self.ticks.get(run, [])[:count]


class LiveThrottle:
    """For a unittest.TestCase whose `throttle` list collects environment/throttle: waiting on a live run."""

    def wait_for(self, what, predicate, timeout=30):
        deadline = time.time() + timeout
        while time.time() < deadline:
            if predicate():
                return
            time.sleep(0.02)
        self.fail('not within %.0f s: %s' % (timeout, what))

    def throttle_after(self, tick):
        self.wait_for('a throttle after tick %d' % tick, lambda: self.throttle and self.throttle[-1].tick > tick)
        return self.throttle[-1]


def open_bag(path, timeout=20.0):
    """Opens a bag for reading, waiting until its writer has closed it."""
    deadline = time.time() + timeout
    while True:
        try:
            return rosbag.Bag(path)
        except Exception as err:  # still being written, or not there yet
            if time.time() > deadline:
                raise AssertionError('bag %s not readable within %.0f s: %s' % (path, timeout, err))
            time.sleep(0.2)


def series(intervals):
    """The comparable content of a metrics/performance series."""
    return [(m.tick_end, m.interval_ticks, m.P, m.p, m.n_ca, m.final, m.swarm_size) for m in intervals]


def removed_at_exit(path):
    """`path`, a folder the test made or named for its nodes, removed when the test process ends (a test
    leaves nothing behind, passed or failed)."""
    atexit.register(shutil.rmtree, path, True)
    return path


def write(folder, name, text):
    """Writes `text` to folder/name; returns the path."""
    path = os.path.join(folder, name)
    with open(path, 'w') as f:
        f.write(text)
    return path
