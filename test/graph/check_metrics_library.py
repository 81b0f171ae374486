#!/usr/bin/env python3
"""Live e, Z, R and A against a run library equal what metrics/compute gives on the same bags.

Three CRW runs in a 10x5 arena are recorded into the library, in order: N=4 ideal, N=8 ideal,
N=8 step_down beta=0.4. The metrics_node of the .test follows each of them live; afterwards a corrupt
bag is added and metrics/compute turns the directory into tables."""
import csv
import io
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import rospy
import rostest
from swarm_forage.msg import (FlexibilityMetric, IntervalPerformance, ScalabilityMetric,
                              SelfOrganizationMetric)
from swarm_forage.srv import Compute
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit  # noqa: E402

TICKS = 4000
INTERVAL = 500
RUNS = [  # (N, waveform, beta)
    (4, 'null', 0.0),
    (8, 'null', 0.0),
    (8, 'step_down', 0.4),
]


class Listener:
    """Every message of every metric topic, in arrival order."""

    def __init__(self):
        self.messages = {}
        for topic, kind in [('scalability', ScalabilityMetric), ('self_organization', SelfOrganizationMetric),
                            ('reactivity', FlexibilityMetric), ('adaptability', FlexibilityMetric),
                            ('performance', IntervalPerformance)]:
            self.messages[topic] = []
            rospy.Subscriber('/metrics/' + topic, kind, self.messages[topic].append, queue_size=1000)

    def count(self, topic):
        return len(self.messages[topic])


def run_once(library, arena, n, waveform, beta, listener):
    """Runs one graph (without its own metrics_node) until the library's metrics_node has its final
    sample; returns the index of the run's first message on each topic."""
    start = {topic: listener.count(topic) for topic in listener.messages}
    cmd = ['roslaunch', 'swarm_forage', 'foraging.launch', 'metrics:=false', 'record:=true',
           'library:=' + library, 'arena:=' + arena, 'n_robots:=%d' % n, 'ticks:=%d' % TICKS,
           'waveform:=' + waveform, 'beta:=%g' % beta, 'exit_when_done:=false', 'required:=false',
           'wait_for_subscribers:=1']
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
    deadline = time.time() + 600  # far above a loaded machine's slowest; ends on the event
    try:
        while time.time() < deadline:
            done = listener.messages['performance'][start['performance']:]
            if done and done[-1].final and listener.count('adaptability') > start['adaptability'] and \
                    listener.messages['adaptability'][-1].final:
                return start
            time.sleep(0.1)
        raise AssertionError('run N=%d %s: no final metrics within 120 s' % (n, waveform))
    finally:
        proc.send_signal(signal.SIGINT)
        proc.wait(timeout=30)


def table(text):
    return list(csv.DictReader(io.StringIO(text)))


class TestMetricsLibrary(unittest.TestCase):
    def test_live_metrics_equal_compute(self):
        rospy.init_node('check_metrics_library')
        library = removed_at_exit(rospy.get_param('~library'))
        arena = rospy.get_param('~arena')
        listener = Listener()
        time.sleep(1.0)
        starts = [run_once(library, arena, n, w, b, listener) for n, w, b in RUNS]

        def live(topic, run_index):
            begin = starts[run_index][topic]
            end = starts[run_index + 1][topic] if run_index + 1 < len(starts) else listener.count(topic)
            return listener.messages[topic][begin:end]

        samples = TICKS // INTERVAL
        # N=4 ideal: nothing smaller in the library yet.
        sc4 = live('scalability', 0)
        self.assertEqual(len(sc4), samples)
        self.assertFalse(sc4[-1].valid)
        self.assertIn('N < 4', sc4[-1].status)
        # N=8 ideal: a running value every sample, against N=4; Z without an N=1 run says so.
        sc8 = live('scalability', 1)
        self.assertEqual(len(sc8), samples)
        self.assertEqual([m.final for m in sc8], [False] * (samples - 1) + [True])
        self.assertTrue(sc8[-1].valid, sc8[-1].status)
        self.assertEqual((sc8[-1].N1, sc8[-1].N2), (4, 8))
        self.assertEqual(len(sc8[-1].e_t), samples)
        self.assertEqual(len(sc8[-1].e_t_valid), samples)  # each sample says whether its e(t) is measured
        for value, valid in zip(sc8[-1].e_t, sc8[-1].e_t_valid):
            if not valid:
                self.assertEqual(value, 0.0)
        z8 = live('self_organization', 1)[-1]
        self.assertTrue(z8.valid, z8.status)
        self.assertIn('N = 1', z8.status)
        self.assertIn('ideal', live('reactivity', 1)[-1].status)
        # N=8 step_down: R and A against the N=8 ideal run; no smaller step_down run for e.
        r8, a8 = live('reactivity', 2)[-1], live('adaptability', 2)[-1]
        self.assertTrue(r8.valid and a8.valid, r8.status + ' / ' + a8.status)
        self.assertEqual(len(r8.ideal), samples)
        sc8s = live('scalability', 2)[-1]
        self.assertFalse(sc8s.valid)
        self.assertIn('step_down', sc8s.status)
        for topic in listener.messages:
            for m in listener.messages[topic]:
                for field in ('e', 'phi', 'Z_sum', 'Z_mean', 'distance', 'n_ca'):
                    if hasattr(m, field):
                        self.assertTrue(abs(getattr(m, field)) < float('inf'), '%s.%s' % (topic, field))

        # The bags, plus a corrupt one, through metrics/compute.
        with open(os.path.join(library, 'corrupt.bag'), 'wb') as f:
            f.write(b'#ROSBAG V2.0\nthis is not a bag')
        rospy.wait_for_service('/metrics/compute', timeout=10)
        out = os.path.join(library, 'tables')
        res = rospy.ServiceProxy('/metrics/compute', Compute)(directory=library, output=out, definitions='')
        self.assertTrue(res.success, res.message)
        self.assertIn('3 runs', res.message)
        self.assertTrue(any('corrupt.bag' in p for p in res.problems), res.problems)
        self.assertTrue(any('step_down' in p and 'N < 8' in p for p in res.problems), res.problems)
        for path in res.tables:
            self.assertTrue(os.path.isfile(path), path)

        scal = {(r['waveform'], int(r['N2'])): r for r in table(res.scalability)}
        self.assertEqual(float(scal[('null', 8)]['e']), sc8[-1].e)
        self.assertEqual(float(scal[('null', 8)]['phi']), sc8[-1].phi)
        self.assertEqual(scal[('null', 8)]['valid'], '1')
        selforg = {(r['waveform'], int(r['m_i'])): r for r in table(res.self_organization)}
        self.assertEqual(float(selforg[('null', 8)]['Z_sum']), z8.Z_sum)
        self.assertEqual(float(selforg[('null', 8)]['Z_mean']), z8.Z_mean)
        flex = table(res.flexibility)
        self.assertEqual(len(flex), 1)
        self.assertEqual((flex[0]['waveform'], int(flex[0]['N'])), ('step_down', 8))
        self.assertEqual(float(flex[0]['R']), r8.distance)
        self.assertEqual(float(flex[0]['A']), a8.distance)

        # `rosbag play --clock` of the step_down bag into a second metrics_node gives the same R and A.
        replayed = {}
        for topic in ('reactivity', 'adaptability'):
            rospy.Subscriber('/replay/metrics/' + topic, FlexibilityMetric,
                             lambda m, t=topic: replayed.__setitem__(t, m) if m.final else None)
        bag = [f for f in os.listdir(library) if f.endswith('.bag') and 'step_down' in f]
        self.assertEqual(len(bag), 1, os.listdir(library))
        topics = ['/world/run_info', '/world/performance', '/swarm/status']
        subprocess.run(['rosbag', 'play', '--clock', '--quiet', '-r', '50', '--queue=100000', '--wait-for-subscribers',
                        os.path.join(library, bag[0]), '--topics'] + topics +
                       ['%s:=/replay%s' % (t, t) for t in topics], check=True, timeout=120)
        deadline = time.time() + 300
        while len(replayed) < 2 and time.time() < deadline:
            time.sleep(0.1)
        self.assertEqual(replayed['reactivity'].distance, r8.distance)
        self.assertEqual(replayed['adaptability'].distance, a8.distance)
        self.assertTrue(replayed['reactivity'].valid)

        # A directory that does not exist: a clear failure, not a crash.
        bad = rospy.ServiceProxy('/metrics/compute', Compute)(directory='/nonexistent/runs', output='',
                                                              definitions='')
        self.assertFalse(bad.success)
        self.assertIn('/nonexistent/runs', bad.message)
        # A folder without a usable run: a failure with the reason, not success with empty tables.
        empty = tempfile.mkdtemp(prefix='swarm_forage_empty_')
        try:
            res = rospy.ServiceProxy('/metrics/compute', Compute)(directory=empty, output='', definitions='')
            self.assertFalse(res.success)
            self.assertIn('no usable recorded run (no *.bag file)', res.message)
            self.assertEqual(os.listdir(empty), [])
        finally:
            os.rmdir(empty)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_metrics_library', TestMetricsLibrary, sys.argv)
