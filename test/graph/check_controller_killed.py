#!/usr/bin/env python3
"""Killing controller_node mid-run: world_node names the silent node and the tick within
~step_timeout, exits with code 1, and the bag recorded so far is readable, marked incomplete in its
name and in its world/run_end, and holds every tick before the silent one."""
import os
import re
import subprocess
import sys
import tempfile
import time
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import RunCollector, open_bag, removed_at_exit

TICKS = 1000000


class TestControllerKilled(unittest.TestCase):
    def test_world_reports_and_bag_is_readable(self):
        rospy.init_node('check_controller_killed')
        bag_path = rospy.get_param('~bag')
        removed_at_exit(os.path.dirname(bag_path))
        step_timeout = rospy.get_param('~step_timeout')
        perf = RunCollector()
        stderr = tempfile.TemporaryFile('w+')  # a file, not a pipe: a full pipe would stall the node
        world = subprocess.Popen(
            ['rosrun', 'swarm_forage', 'world_node', '__name:=world', '_ticks:=%d' % TICKS, '_bag:=' + bag_path,
             '_step_timeout:=%g' % step_timeout, '_wait_for_subscribers:=1', '_seed:=1'],
            stdout=subprocess.DEVNULL, stderr=stderr, text=True)
        try:
            deadline = time.time() + 600  # far above a loaded machine's slowest; ends on the event
            while len(perf.ticks.get(0, [])) < 300:
                self.assertLess(time.time(), deadline, 'the run did not reach tick 300')
                self.assertIsNone(world.poll(), 'world_node ended early')
                time.sleep(0.05)
            subprocess.run(['rosnode', 'kill', '/controller'], check=True, timeout=30)
            killed_at = time.time()
            world.wait(timeout=step_timeout + 30)
        finally:
            if world.poll() is None:
                world.kill()
        stderr.seek(0)
        err = stderr.read()
        self.assertLess(time.time() - killed_at, step_timeout + 10)
        self.assertEqual(world.returncode, 1, err)
        report = re.search(r'run 0 stopped at tick (\d+) of %d \((.*)\)' % TICKS, err)
        self.assertIsNotNone(report, 'world_node said nothing about the stop on stderr:\n' + err)
        tick, reason = int(report.group(1)), report.group(2)
        self.assertIn('/controller', reason)
        self.assertIn('swarm/commands', reason)
        self.assertIn('step_timeout', reason)
        self.assertNotIn('finished', err)

        self.assertFalse(os.path.exists(bag_path), 'an interrupted run must not take the complete name')
        incomplete = bag_path.replace('.bag', '_incomplete.bag')
        bag = open_bag(incomplete)
        ticks = [m.tick for _, m, _ in bag.read_messages(topics=['/world/performance'])]
        ends = [m for _, m, _ in bag.read_messages(topics=['/world/run_end'])]
        bag.close()
        self.assertEqual(ticks, list(range(tick)), 'the bag must hold every tick before the silent one')
        self.assertEqual(len(ends), 1)
        self.assertFalse(ends[0].complete)
        self.assertEqual((ends[0].ticks_done, ends[0].ticks), (tick, TICKS))
        self.assertEqual(ends[0].reason, reason)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_controller_killed', TestControllerKilled, sys.argv)
