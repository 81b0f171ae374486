#!/usr/bin/env python3
"""A bag recorded by foraging.launch record:=true, replayed with `rosbag play --clock` into a fresh
metrics_node, reproduces the live metrics/performance series exactly."""
import os
import subprocess
import sys
import unittest

import rospy
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import RunCollector, open_bag, removed_at_exit, series

TICKS = 2000
RECORDED = ['/world/performance', '/swarm/status', '/environment/throttle']
REPLAYED = ['/world/run_info', '/world/performance', '/swarm/status']  # what metrics_node reads


class TestReplay(unittest.TestCase):
    def test_replay_reproduces_live_metrics(self):
        rospy.init_node('check_replay')
        bag_path = rospy.get_param('~bag')
        removed_at_exit(os.path.dirname(bag_path))
        live = RunCollector()
        # Not subscribed to /replay/world/performance: rosbag's --wait-for-subscribers must wait for the
        # replay metrics_node itself (a test subscriber satisfied it first, and the node missed ticks).
        replay = RunCollector(None, '/replay/metrics/performance')
        live_series = series(live.wait_final(0, timeout=240))
        self.assertGreater(len(live_series), 1)

        bag = open_bag(bag_path)
        counts = {t: bag.get_message_count(t) for t in RECORDED}
        bag.close()
        self.assertEqual(counts['/world/performance'], TICKS, 'one world/performance per tick')
        self.assertEqual(counts['/swarm/status'], TICKS)
        # An ideal run's condition never changes: recorded once, at tick 0 (V per tick is in world/performance).
        self.assertEqual(counts['/environment/throttle'], 1)

        remaps = ['%s:=/replay%s' % (t, t) for t in REPLAYED]
        cmd = ['rosbag', 'play', '--clock', '--quiet', '-r', '100', '--queue=100000', '--wait-for-subscribers',
               bag_path, '--topics'] + REPLAYED + remaps
        subprocess.run(cmd, check=True, timeout=120)
        replayed = series(replay.wait_final(0, timeout=60))
        self.assertEqual(replayed, live_series)
        # The same bag again into the same node: a second, identical run, not one lost.
        replay.intervals.clear()
        subprocess.run(cmd, check=True, timeout=120)
        self.assertEqual(series(replay.wait_final(0, timeout=60)), live_series)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_replay', TestReplay, sys.argv)
