#!/usr/bin/env python3
"""The full graph: blocks are delivered, P never decreases, world/performance once per tick in sim
time, the documented topics exist, world/info answers, and the same seed twice gives the same P series."""
import os
import sys
import unittest

import rosgraph
import rospy
import rostest
from swarm_forage.srv import Info, Reset

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import RunCollector, series

TICKS = 3000


class TestForagingGraph(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_graph')
        cls.collector = RunCollector()

    def test_graph(self):
        c = self.collector
        run0 = c.wait_final(0, timeout=240)
        ticks = c.wait_ticks(0, TICKS, timeout=60)
        # Once per tick, in order, stamped with simulated time tick * 0.2 s.
        self.assertEqual([m.tick for m in ticks], list(range(TICKS)))
        for m in ticks:
            self.assertEqual(m.header.stamp.to_nsec(), m.tick * 200000000)
        self.assertTrue(ticks[-1].last)
        # Blocks are delivered; P never decreases and is the sum of the per-tick deliveries.
        cumulative = [m.cumulative for m in ticks]
        self.assertTrue(all(b >= a for a, b in zip(cumulative, cumulative[1:])), 'P decreased')
        self.assertEqual(cumulative[-1], sum(m.delivered for m in ticks))
        self.assertGreater(cumulative[-1], 0, 'no block delivered in %d ticks' % TICKS)
        self.assertEqual(run0[-1].P, cumulative[-1])
        self.assertEqual(sum(s.interval_ticks for s in run0), TICKS)

        # The documented topics (docs/node-graph.md) are on the graph.
        published = {t for t, _ in rosgraph.Master('/check_graph').getPublishedTopics('')}
        for topic in ['/clock', '/world/sensors', '/swarm/commands', '/environment/throttle', '/swarm/status',
                      '/world/performance', '/world/robots', '/world/blocks', '/world/nest', '/world/run_info',
                      '/metrics/performance']:
            self.assertIn(topic, published)

        rospy.wait_for_service('world/info', 10)
        info = rospy.ServiceProxy('world/info', Info)()
        self.assertEqual(info.run.swarm_size, 64)
        self.assertEqual(info.run.arena, '32x16')
        self.assertAlmostEqual(info.nest.center_x, 3.2, places=4)

        # A bad reset is refused with the parameter named; a good one replays the seed.
        reset = rospy.ServiceProxy('world/reset', Reset)
        bad = reset(seed=0, swarm_size=100000, controller='')
        self.assertFalse(bad.success)
        self.assertIn('n_robots', bad.message)
        self.assertFalse(reset(seed=0, swarm_size=0, controller='nope').success)
        big = reset(seed=4294967295, swarm_size=0, controller='')
        self.assertFalse(big.success)
        self.assertIn('seed must be in [0, 2147483647]', big.message)
        again = reset(seed=info.run.seed, swarm_size=64, controller='crw')
        self.assertTrue(again.success, again.message)
        run1 = c.wait_final(again.run, timeout=240)
        self.assertEqual([m.cumulative for m in c.wait_ticks(again.run, TICKS, timeout=60)], cumulative)
        self.assertEqual(series(run1), series(run0))


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_graph', TestForagingGraph, sys.argv)
