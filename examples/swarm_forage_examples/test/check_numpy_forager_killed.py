#!/usr/bin/env python3
"""Killing the rospy controller mid-run is reported like controller_node's death: world_node names the
silent node, its topic and the tick within ~step_timeout, exits with code 1, and the bag recorded so far
is marked incomplete and holds every tick before the silent one."""
import os
import re
import subprocess
import sys
import tempfile
import time
import unittest

import rospy
import rostest

from forager_graph import RunCollector, read_bag, removed_at_exit, wait_up, world

TICKS = 1000000
STEP_TIMEOUT = 5.0


class TestNumpyForagerKilled(unittest.TestCase):
    def test_world_names_the_killed_node(self):
        rospy.init_node('check_numpy_forager_killed')
        perf = RunCollector(metrics_topic='metrics/performance')
        bag = os.path.join(removed_at_exit(tempfile.mkdtemp(prefix='numpy_forager_killed_')), 'killed.bag')
        wait_up(['/numpy_forager'])  # started by the launch file
        w = world(bag, controller='numpy_forager', external_controller='numpy_forager', ticks=TICKS,
                  step_timeout=STEP_TIMEOUT, wait_for_subscribers=1)
        try:
            deadline = time.time() + 300
            while len(perf.ticks.get(0, [])) < 300:  # ticks advance only with the node's answers
                self.assertLess(time.time(), deadline, 'the run did not reach tick 300')
                self.assertIsNone(w.proc.poll(), 'world_node ended early:\n' + w.stderr())
                time.sleep(0.05)
            subprocess.run(['rosnode', 'kill', '/numpy_forager'], check=True, timeout=30)
            code = w.wait(timeout=STEP_TIMEOUT + 60)
        finally:
            w.stop()
        err = w.stderr()
        self.assertEqual(code, 1, err)
        report = re.search(r'run 0 stopped at tick (\d+) of %d \((.*)\)' % TICKS, err)
        self.assertIsNotNone(report, 'world_node said nothing about the stop on stderr:\n' + err)
        tick, reason = int(report.group(1)), report.group(2)
        self.assertGreaterEqual(tick, 300)
        for word in ('/numpy_forager', 'step_timeout', 'tick %d' % tick):
            self.assertIn(word, reason)
        # The node sends a tick's commands and then its status: killed between the two, the status is what
        # world_node still waits for; either names the topic that went silent.
        self.assertRegex(reason, r'robots \[0, 64\) on swarm/(commands|status) from /numpy_forager')

        self.assertFalse(os.path.exists(bag), 'an interrupted run must not take the complete name')
        run = read_bag(bag.replace('.bag', '_incomplete.bag'))
        self.assertEqual([p.tick for p in run['/world/performance']], list(range(tick)))
        ends = run['/world/run_end']
        self.assertEqual(len(ends), 1)
        self.assertFalse(ends[0].complete)
        self.assertEqual((ends[0].ticks_done, ends[0].reason), (tick, reason))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'check_numpy_forager_killed', TestNumpyForagerKilled, sys.argv)
