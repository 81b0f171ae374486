#!/usr/bin/env python3
"""world/markers of a GP-DPO swarm: one task square per robot (ns "tasks": generalist white, harvester
magenta, collector dark blue), each over the robot's state sphere, and the static cache with its count."""
import sys
import time
import unittest

import rospy
import rostest
from visualization_msgs.msg import Marker, MarkerArray

N = 256
TASK_COLOURS = {0: (1.0, 1.0, 1.0), 1: (0.85, 0.1, 0.6), 2: (0.1, 0.2, 0.8)}


class TestGpDpoMarkers(unittest.TestCase):
    def test_tasks(self):
        rospy.init_node('check_markers_gp_dpo')
        got = []
        rospy.Subscriber('world/markers', MarkerArray, got.append, queue_size=20)
        deadline = time.time() + 600
        while len(got) < 3 and time.time() < deadline:
            time.sleep(0.05)
        self.assertGreaterEqual(len(got), 3, 'world/markers did not arrive')
        seen = set()
        for msg in got[1:]:  # the first may precede the controllers' first answer
            tasks = [m for m in msg.markers if m.ns == 'tasks']
            robots = [m for m in msg.markers if m.ns == 'robots']
            self.assertEqual(sorted(m.id for m in tasks), [0, 1, 2])
            self.assertEqual(sum(len(m.points) for m in tasks if m.action == Marker.ADD), N)
            self.assertEqual(sum(len(m.points) for m in robots if m.action == Marker.ADD), N)
            spheres = {(round(p.x, 4), round(p.y, 4)) for m in robots for p in m.points}
            for m in tasks:
                if m.action != Marker.ADD:
                    continue
                seen.add(m.id)
                self.assertEqual(m.type, Marker.CUBE_LIST)
                for want, have in zip(TASK_COLOURS[m.id], (m.color.r, m.color.g, m.color.b)):
                    self.assertAlmostEqual(want, have, places=5)
                for p in m.points:
                    self.assertIn((round(p.x, 4), round(p.y, 4)), spheres)
                    self.assertGreater(p.z, 2 * 0.085)  # drawn on top of the sphere
            cache = [m for m in msg.markers if m.ns == 'cache']
            self.assertTrue(any(m.type == Marker.TEXT_VIEW_FACING and m.text.startswith('cache: ') and
                                m.action == Marker.ADD for m in cache))
        self.assertTrue(seen, 'no task shown')
        print('tasks shown: %s' % sorted(seen))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'markers_gp_dpo', TestGpDpoMarkers, sys.argv)
