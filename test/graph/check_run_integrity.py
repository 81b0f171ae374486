#!/usr/bin/env python3
"""Runs never mix and nothing is lost: run identity and bag names, duplicates, interrupted
runs, a long-lived metrics_node after an interruption, and checks of how robots are split across
controller nodes. Every graph is started through `rosrun swarm_forage forage`, which exits non-zero
with the reason when a run did not reach its last tick."""
import glob
import os
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rospy
import rostest
from swarm_forage.msg import IntervalPerformance, Performance
from swarm_forage.srv import Compute, Reset

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import open_bag, removed_at_exit

TICKS = 300


# Two subscribers of world/performance: this test and the long-lived metrics_node, which must not miss tick 0.
FORAGE = ['rosrun', 'swarm_forage', 'forage', 'metrics:=false', 'wait_for_subscribers:=2']


def forage(*args, timeout=120):
    """Runs one graph to its end; returns (exit code, everything it printed)."""
    proc = subprocess.run(FORAGE + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          timeout=timeout)
    return proc.returncode, proc.stdout


def launch_graph(*args):
    """Starts one graph in a session of its own: a SIGINT to its group is a terminal's Ctrl-C."""
    return subprocess.Popen(FORAGE + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            start_new_session=True)


class Ticks:
    """world/performance ticks and final metrics/performance samples as they arrive."""

    def __init__(self):
        self.performance = []
        self.finals = []
        rospy.Subscriber('/world/performance', Performance, self.performance.append, queue_size=100000)
        rospy.Subscriber('/metrics/performance', IntervalPerformance,
                         lambda m: self.finals.append(m) if m.final else None, queue_size=10000)

    def wait(self, predicate, timeout, what):
        deadline = time.time() + max(timeout, 300)  # a bound for failure only: far above a loaded machine's pauses
        while not predicate():
            if time.time() > deadline:
                raise AssertionError('timed out waiting for ' + what)
            time.sleep(0.05)


class TestRunIntegrity(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_run_integrity')
        cls.library = removed_at_exit(rospy.get_param('~library'))
        cls.arena = rospy.get_param('~arena')
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_integrity_'))
        # Another arena that calls itself 10x5 too, one metre wider.
        cls.wider = os.path.join(cls.tmp, 'wider.yaml')
        with open(cls.wider, 'w') as f:
            f.write('name: 10x5\nwidth: 11.0\nheight: 5.0\nblocks: 9\n')
        cls.ticks = Ticks()
        rospy.wait_for_service('/metrics/compute', timeout=30)
        time.sleep(1.0)

    def compute(self, directory, sample_interval=0):
        return rospy.ServiceProxy('/metrics/compute', Compute)(directory=directory, output=os.path.join(
            self.tmp, 'tables'), definitions='', sample_interval=sample_interval)

    def run_into(self, directory, *args):
        code, out = forage('arena:=' + self.arena, 'n_robots:=4', 'ticks:=%d' % TICKS, 'seed:=5', 'record:=true',
                           'results:=' + directory, *args)
        self.assertEqual(code, 0, out)
        self.assertIn('forage: run 0 complete: %d of %d ticks' % (TICKS, TICKS), out)
        return out

    def long_run(self, directory, seed, *args):
        """Starts a run far longer than the test: it ends only when interrupted."""
        return launch_graph('arena:=' + self.arena, 'n_robots:=4', 'ticks:=1000000', 'seed:=%d' % seed,
                            'record:=true', 'results:=' + directory, *args)

    def test_1_identity_arenas_alpha_and_duplicates(self):
        lib = os.path.join(self.tmp, 'identity')
        self.run_into(lib)
        self.run_into(lib, 'arena:=' + self.wider)  # the same name, other geometry
        self.run_into(lib, 'waveform:=step_up', 'beta:=0.4', 'alpha:=20')
        self.run_into(lib, 'waveform:=step_up', 'beta:=0.4', 'alpha:=40')  # differs only in alpha
        bags = sorted(os.listdir(lib))
        self.assertEqual(len(bags), 4, bags)
        self.assertEqual(len([b for b in bags if 'step_up0.4_seed5' in b]), 2, bags)
        identities = set()
        for b in bags:
            with rosbag.Bag(os.path.join(lib, b)) as bag:
                info = next(m for _, m, _ in bag.read_messages(topics=['/world/run_info']))
            self.assertIn(info.identity, b)
            identities.add(info.identity)
        self.assertEqual(len(identities), 4)
        res = self.compute(lib)
        self.assertTrue(res.success, res.message)
        self.assertIn('4 runs in 4 groups', res.message)
        self.assertIn('sample interval 100 ticks', res.message)

        # The same run again: a second bag, never a silent replacement; the library lists it.
        self.run_into(lib)
        self.assertEqual(len(os.listdir(lib)), 5)
        res = self.compute(lib)
        self.assertIn('4 runs in 4 groups', res.message)
        duplicates = [p for p in res.problems if 'the same run' in p]
        self.assertEqual(len(duplicates), 1, res.problems)
        self.assertIn('seed 5', duplicates[0])
        self.assertIn('identical series', duplicates[0])
        # Another sample interval is the caller's to choose, and the tables say which was used.
        res = self.compute(lib, sample_interval=50)
        self.assertIn('sample interval 50 ticks', res.message)
        self.assertIn(',50,', res.scalability.splitlines()[1])

    def test_2_interrupted_runs_are_marked_and_left_out(self):
        lib = os.path.join(self.tmp, 'interrupted')
        self.run_into(lib)
        # Ctrl-C mid-run.
        start = len(self.ticks.performance)
        proc = self.long_run(lib, 6)
        self.ticks.wait(lambda: len(self.ticks.performance) > start + 200, 60, 'the long run to start')
        # A world/reset mid-run ends run 0 early; then Ctrl-C ends run 1.
        reset = rospy.ServiceProxy('/world/reset', Reset)
        reset.wait_for_service(10)
        self.assertTrue(reset(seed=9, swarm_size=0, controller='').success)
        start = len(self.ticks.performance)
        self.ticks.wait(lambda: sum(1 for m in self.ticks.performance[start:] if m.run == 1) > 100, 60,
                        'run 1 to start')
        os.killpg(proc.pid, signal.SIGINT)
        out, _ = proc.communicate(timeout=60)
        self.assertNotEqual(proc.returncode, 0, out)
        self.assertRegex(out, r'run 0 stopped at tick \d+ of 1000000 \(world/reset at tick \d+\)')
        self.assertRegex(out, r'run 1 stopped at tick \d+ of 1000000 \(node shut down')
        self.assertNotIn('finished', out)
        incomplete = glob.glob(os.path.join(lib, '*_incomplete.bag'))
        self.assertEqual(len(incomplete), 2, os.listdir(lib))
        reasons = []
        for path in incomplete:
            bag = open_bag(path)
            end = [m for _, m, _ in bag.read_messages(topics=['/world/run_end'])]
            bag.close()
            self.assertEqual(len(end), 1)
            self.assertFalse(end[0].complete)
            reasons.append(end[0].reason)
        self.assertTrue(any('world/reset' in r for r in reasons) and any('shut down' in r for r in reasons), reasons)

        # A controller that dies (not required: the world notices it): forage, not roslaunch (which exits 0),
        # fails with the reason.
        proc = self.long_run(lib, 7, 'step_timeout:=1.0', 'required:=false')
        start = len(self.ticks.performance)
        self.ticks.wait(lambda: len(self.ticks.performance) > start + 200, 60, 'the second long run to start')
        subprocess.run(['rosnode', 'kill', '/controller'], check=True, timeout=30)
        out, _ = proc.communicate(timeout=60)
        self.assertEqual(proc.returncode, 1, out)
        self.assertRegex(out, r'forage: run 0 stopped at tick \d+ of 1000000 \(tick \d+: no reply within '
                              r'~step_timeout 1.00 s: robots \[0, 4\) on swarm/commands from /controller')

        res = self.compute(lib)
        self.assertTrue(res.success, res.message)
        self.assertIn('1 runs in 1 groups', res.message)
        left_out = [p for p in res.problems if 'incomplete' in p]
        self.assertEqual(len(left_out), 3, res.problems)
        self.assertTrue(any('shut down' in p for p in left_out), left_out)
        self.assertTrue(any('/controller' in p for p in left_out), left_out)

    def test_3_long_lived_metrics_node_follows_the_run_after_an_interrupted_one(self):
        lib = os.path.join(self.tmp, 'follow')
        # Twice in a row, then a complete run. The first is cut in its run 1 (after a world/reset): the
        # next world starts again at run 0, a lower number than the run the node was following.
        for interrupted in range(2):
            proc = self.long_run(lib, 8)
            start = len(self.ticks.performance)
            self.ticks.wait(lambda: len(self.ticks.performance) > start + 150, 60, 'a long run to start')
            if interrupted == 0:
                reset = rospy.ServiceProxy('/world/reset', Reset)
                reset.wait_for_service(10)
                self.assertTrue(reset(seed=0, swarm_size=0, controller='').success)
                self.ticks.wait(lambda: sum(1 for m in self.ticks.performance[start:] if m.run == 1) > 100, 60,
                                'run 1 to start')
            os.killpg(proc.pid, signal.SIGINT)
            proc.communicate(timeout=60)
        finals = len(self.ticks.finals)
        self.run_into(lib, 'n_robots:=6')
        self.ticks.wait(lambda: len(self.ticks.finals) > finals, 30, 'the final sample of the run after them')
        final = self.ticks.finals[-1]
        self.assertEqual((final.swarm_size, final.tick_end, final.run), (6, TICKS - 1, 0))
        self.assertEqual(sum(1 for m in self.ticks.finals[finals:]), 1)

    def test_4_controller_ranges_are_checked_from_tick_0(self):
        upper = ['rosrun', 'swarm_forage', 'controller_node', '__name:=controller_upper', '_first_id:=32']
        for count, words in [('0', ['robots [32, 64) on swarm/', 'are claimed by both /controller ([0, 64)) '
                                    'and /controller_upper ([32, 64))']),
                             ('30', ['robots [30, 32) on swarm/commands: no node serves them',
                                     '/controller serves [0, 30)', '/controller_upper serves [32, 64)'])]:
            node = subprocess.Popen(upper, stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT)
            try:
                code, out = forage('n_robots:=64', 'ticks:=%d' % TICKS, 'controller_count:=' + count,
                                   'step_timeout:=4.0', 'wait_for_subscribers:=0')
            finally:
                node.send_signal(signal.SIGINT)
                node.wait(timeout=30)
            self.assertEqual(code, 1, out)
            # A gap stops tick 0 (the world waits for the robots no node serves); an overlap stops the tick the
            # second node's status first arrives, which a loaded machine may delay past tick 0.
            tick = r'0' if count == '30' else r'\d+'
            self.assertRegex(out, r'forage: run 0 stopped at tick (%s) of %d \(tick \1: ' % (tick, TICKS))
            for w in words:
                self.assertIn(w, out)

    def test_5_realtime_reports_a_killed_controller(self):
        proc = launch_graph('arena:=' + self.arena, 'n_robots:=4', 'ticks:=1000000', 'mode:=realtime',
                            'real_time_factor:=20', 'step_timeout:=1.5', 'required:=false')
        start = len(self.ticks.performance)
        self.ticks.wait(lambda: len(self.ticks.performance) > start + 50, 60, 'the realtime run to start')
        subprocess.run(['rosnode', 'kill', '/controller'], check=True, timeout=30)
        killed = time.time()
        out, _ = proc.communicate(timeout=60)
        self.assertLess(time.time() - killed, 15)
        self.assertEqual(proc.returncode, 1, out)
        self.assertRegex(out, r'run 0 stopped at tick \d+ of 1000000 \(tick \d+: /controller \(robots \[0, 4\)\) '
                              r'has sent no swarm/commands for [\d.]+ s \(~step_timeout 1.50 s, realtime\)')


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_run_integrity', TestRunIntegrity, sys.argv)
