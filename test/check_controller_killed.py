#!/usr/bin/env python3
"""Killing controller_node mid-run: world_node names the silent node and the tick within
~step_timeout, and the bag recorded so far is readable, holding every tick before that one."""
import re
import subprocess
import sys
import time
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Log

from graph_helpers import RunCollector, open_bag


class TestControllerKilled(unittest.TestCase):
    def test_world_reports_and_bag_is_readable(self):
        rospy.init_node('check_controller_killed')
        bag_path = rospy.get_param('~bag')
        step_timeout = rospy.get_param('~step_timeout')
        errors = []
        rospy.Subscriber('/rosout', Log, lambda m: errors.append(m) if m.level >= Log.ERROR else None,
                         queue_size=1000)
        perf = RunCollector()
        deadline = time.time() + 120
        while len(perf.ticks.get(0, [])) < 300:
            self.assertLess(time.time(), deadline, 'the run did not reach tick 300')
            time.sleep(0.05)
        subprocess.run(['rosnode', 'kill', '/controller'], check=True, timeout=30)
        killed_at = time.time()

        report = None
        while report is None and time.time() < killed_at + step_timeout + 20:
            report = next((m for m in errors if m.name == '/world' and 'step_timeout' in m.msg), None)
            time.sleep(0.05)
        self.assertIsNotNone(report, 'world_node reported nothing; errors seen: %s' % [m.msg for m in errors])
        self.assertIn('/controller', report.msg)
        self.assertIn('swarm/commands', report.msg)
        tick = int(re.search(r'tick (\d+)', report.msg).group(1))
        self.assertLess(time.time() - killed_at, step_timeout + 10)

        bag = open_bag(bag_path)
        ticks = [m.tick for _, m, _ in bag.read_messages(topics=['/world/performance'])]
        bag.close()
        self.assertEqual(ticks, list(range(tick)), 'the bag must hold every tick before the silent one')


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_controller_killed', TestControllerKilled, sys.argv)
