#!/usr/bin/env python3
"""One graph, two ways to run it: `forage nodelet:=true` (the four nodes as nodelets in one process) ends
its run the way `forage` (four processes) does, and records the same bag message for message (topic, time
and bytes), for each controller kind. A lockstep run does not depend on how its nodes are scheduled."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rostest

ARGS = ['n_robots:=16', 'arena:=32x16', 'ticks:=600', 'seed:=5', 'waveform:=sine', 'beta:=0.3', 'frequency:=0.01',
        'record_every:=100', 'sample_interval:=200', 'record:=true', 'threads:=2']


class TestNodeletGraph(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_nodelet_graph_')

    def tearDown(self):
        shutil.rmtree(self.tmp)

    def forage(self, controller, nodelet):
        bag = os.path.join(self.tmp, '%s_%s.bag' % (controller, nodelet))
        proc = subprocess.run(['rosrun', 'swarm_forage', 'forage', 'controller:=' + controller, 'bag:=' + bag,
                               'nodelet:=' + nodelet] + ARGS, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                              text=True, timeout=300)
        self.assertEqual(proc.returncode, 0, proc.stdout[-3000:])
        self.assertIn('forage: run 0 complete: 600 of 600 ticks; bag: ' + bag, proc.stdout)
        return bag

    def test_same_bag_both_ways(self):
        for controller in ('crw', 'dpo', 'gp_dpo'):
            with self.subTest(controller=controller):
                nodes, nodelets = self.forage(controller, 'false'), self.forage(controller, 'true')
                same = subprocess.run(['rosrun', 'swarm_forage', 'compare_bags', nodes, nodelets],
                                      stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
                self.assertEqual(same.returncode, 0, same.stdout)
                self.assertIn('identical', same.stdout)
                print(controller, same.stdout.strip())


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'nodelet_graph', TestNodeletGraph, sys.argv)
