#!/usr/bin/env python3
"""world/markers on a 16,384-robot world: frame map, the arena's static markers, one robot point per robot
in the four class markers, each class in its documented colour, and no more than ~markers_rate messages
a wall second. Prints the message size and the rate seen."""
import io
import sys
import time
import unittest

import rospy
import rostest
import tf2_ros
from diagnostic_msgs.msg import DiagnosticArray
from rosgraph_msgs.msg import Clock
from visualization_msgs.msg import Marker, MarkerArray

N = 16384
RATE = 4.0
COLOURS = {0: (1.0, 0.55, 0.0), 1: (0.9, 0.1, 0.1), 2: (0.1, 0.8, 0.2), 3: (0.4, 0.7, 1.0)}  # docs/watching-and-tuning.md


def world_status_value(key):
    """`key` of world_node's next status on /diagnostics (other nodes' messages are skipped)."""
    while True:
        for status in rospy.wait_for_message('/diagnostics', DiagnosticArray, timeout=10).status:
            if status.name == 'world: stepping':
                return {kv.key: kv.value for kv in status.values}[key]


class TestMarkers(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_markers')

    def test_markers(self):
        got, ticks = [], []
        rospy.Subscriber('world/markers', MarkerArray, lambda m: got.append((time.time(), m)), queue_size=20)
        rospy.Subscriber('/clock', Clock, lambda m: ticks.append(time.time()), queue_size=1000)
        deadline = time.time() + 600  # far above a loaded machine's slowest; ends on the event
        while not got and time.time() < deadline:
            time.sleep(0.1)
        self.assertTrue(got, 'no world/markers within 600 s')
        time.sleep(5.0)
        first = got[0][0]
        window = [m for t, m in got if t >= first + 0.5 and t < first + 5.0]
        rate = len(window) / 4.5
        # Markers come with ticks: a loaded machine that steps fewer than ~markers_rate ticks a second
        # publishes fewer, which is right.
        stepped = len([t for t in ticks if first + 0.5 <= t < first + 5.0])
        buf = io.BytesIO()
        got[-1][1].serialize(buf)
        build = world_status_value('markers build and publish [ms]')
        print('world/markers: %d messages in 4.5 s (%.2f/s, ~markers_rate %.0f; %d ticks), %d bytes each, '
              '%d markers, %s ms to build and publish'
              % (len(window), rate, RATE, stepped, len(buf.getvalue()), len(got[-1][1].markers), build))
        self.assertGreater(float(build), 0.0)
        self.assertLessEqual(rate, RATE * 1.3)
        self.assertGreaterEqual(len(window), 0.4 * min(RATE * 4.5, stepped))
        for _, msg in got:
            by_ns = {}
            for m in msg.markers:
                self.assertEqual(m.header.frame_id, 'map')
                by_ns.setdefault(m.ns, []).append(m)
            for ns in ('arena', 'nest', 'lights', 'blocks', 'robots'):
                self.assertIn(ns, by_ns)
            # CRW robots have no task: the task squares are deleted.
            self.assertEqual([m.action for m in by_ns['tasks']], [Marker.DELETE] * 3)
            robots = by_ns['robots']
            self.assertEqual(sorted(m.id for m in robots), [0, 1, 2, 3])
            self.assertEqual(sum(len(m.points) for m in robots), N)
            for m in robots:
                self.assertEqual(m.type, Marker.SPHERE_LIST)
                self.assertAlmostEqual(m.scale.x, 0.17, places=5)
                for want, have in zip(COLOURS[m.id], (m.color.r, m.color.g, m.color.b)):
                    self.assertAlmostEqual(want, have, places=5)
            blocks = sorted(by_ns['blocks'], key=lambda m: m.id)  # cubes 0.2 m, ramps 0.4 x 0.2 m
            self.assertEqual([(m.scale.x, m.scale.y) for m in blocks], [(0.2, 0.2), (0.4, 0.2)])
            carrying = [m for m in robots if m.id == 0][0]
            # Every block is on the floor or carried (CRW: no cache), at the same tick.
            self.assertEqual(sum(len(m.points) for m in blocks) + len(carrying.points), 460)
        explorers = [m for m in got[-1][1].markers if m.ns == 'robots' and m.id == 3][0]
        self.assertGreater(len(explorers.points), 0)

    def test_tf(self):
        """The static frames and the three robots of ~tf_robots resolve; no other robot has a frame."""
        buf = tf2_ros.Buffer()
        tf2_ros.TransformListener(buf)
        for frame in ('arena', 'nest', 'robot_0', 'robot_5', 'robot_16383'):
            t = buf.lookup_transform('map', frame, rospy.Time(0), rospy.Duration(30))
            self.assertEqual(t.child_frame_id, frame)
            self.assertFalse(t.child_frame_id.startswith('/'))
        nest = buf.lookup_transform('map', 'nest', rospy.Time(0)).transform.translation
        self.assertAlmostEqual(nest.x, 9.6, places=3)  # 96x48: the nest's centre at 0.1 W, H / 2
        self.assertAlmostEqual(nest.y, 24.0, places=3)
        r = buf.lookup_transform('map', 'robot_5', rospy.Time(0)).transform
        self.assertTrue(0 < r.translation.x < 96 and 0 < r.translation.y < 48)
        self.assertAlmostEqual(r.rotation.z ** 2 + r.rotation.w ** 2, 1.0, places=5)
        self.assertFalse(buf.can_transform('map', 'robot_1', rospy.Time(0)))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'markers', TestMarkers, sys.argv)
