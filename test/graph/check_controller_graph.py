#!/usr/bin/env python3
"""One controller kind through two graphs side by side: graph `a` with one controller_node, graph `b`
with the same robots split over two controller_nodes. Both deliver blocks and give identical series;
graph `a` replays the same seed via world/reset identically. For gp_dpo, all three tasks occur and
the static cache is used."""
import os
import sys
import unittest

import rospy
import rostest
from swarm_forage.msg import CacheArray, SwarmStatus
from swarm_forage.srv import Reset

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import RunCollector, series


class TestControllerGraph(unittest.TestCase):
    def test_controller_graph(self):
        rospy.init_node('check_controller_graph')
        controller = rospy.get_param('~controller')
        ticks = rospy.get_param('~ticks')
        tasks_seen = {'generalists': 0, 'harvesters': 0, 'collectors': 0}
        cache_sizes = set()

        def on_status(msg):
            for task in tasks_seen:
                tasks_seen[task] = max(tasks_seen[task], getattr(msg, task))

        rospy.Subscriber('/a/swarm/status', SwarmStatus, on_status, queue_size=100000)
        rospy.Subscriber('/a/world/caches', CacheArray, lambda m: cache_sizes.update(m.blocks or [0]),
                         queue_size=100000)
        a = RunCollector('/a/world/performance', '/a/metrics/performance')
        b = RunCollector('/b/world/performance', '/b/metrics/performance')
        run_a = a.wait_final(0, timeout=400)
        run_b = b.wait_final(0, timeout=400)
        P_a = [m.cumulative for m in a.wait_ticks(0, ticks, timeout=60)]
        self.assertEqual(len(P_a), ticks)
        self.assertGreater(P_a[-1], 0, '%s delivered no block in %d ticks' % (controller, ticks))
        self.assertEqual([m.cumulative for m in b.wait_ticks(0, ticks, timeout=60)], P_a, 'one vs two controller nodes differ')
        self.assertEqual(series(run_b), series(run_a))

        if controller == 'gp_dpo':
            for task, most in tasks_seen.items():
                self.assertGreater(most, 0, 'no robot was ever a %s' % task[:-1])
            self.assertGreater(len(cache_sizes), 1, 'the static cache was never used: sizes %s' % cache_sizes)

        reset = rospy.ServiceProxy('/a/world/reset', Reset)
        reset.wait_for_service(10)
        again = reset(seed=rospy.get_param('~seed'), swarm_size=0, controller='')
        self.assertTrue(again.success, again.message)
        self.assertEqual(series(a.wait_final(again.run, timeout=400)), series(run_a))
        self.assertEqual([m.cumulative for m in a.wait_ticks(again.run, ticks, timeout=60)], P_a, 'same seed, different series')


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_controller_graph', TestControllerGraph, sys.argv)
