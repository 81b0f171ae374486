#!/usr/bin/env python3
"""Sensor and actuator noise keeps a run bit-identical for any thread count and controller split: with
noise on every device, run_experiment on 1, 2 and 3 threads and the node graph with the robots split over
two controller nodes record the same messages (the split graph's swarm/status comes in two ranges); the run's identity carries the noise words, and the same
run without noise differs (the noise is applied)."""
import os
import subprocess
import sys
import tempfile
import unittest

import rostest

from check_headless_identity import messages  # noqa: E402
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import open_bag, removed_at_exit  # noqa: E402

TICKS = 300
COMMON = ['controller:=dpo', 'n_robots:=40', 'ticks:=%d' % TICKS, 'seed:=3']
# Every device; DPO reads the position and heading (its block memory), the proximity, light and ground.
NOISE = {'all': {'model': 'gaussian', 'level': 0.02}, 'light': {'model': 'uniform', 'level': 0.05},
         'ground': {'level': 0.05}}
WORDS = ['noise/all/level:=0.02', 'noise/light/model:=uniform', 'noise/light/level:=0.05', 'noise/ground/level:=0.05']
EXPECTED = ('noise/proximity=gaussian:0.02 noise/light=uniform:0.05 noise/ground=0.05 '
            'noise/position=gaussian:0.02 noise/heading=gaussian:0.02 noise/wheels=gaussian:0.02')


class NoiseGraph(unittest.TestCase):
    def setUp(self):
        self.folder = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_noise_'))

    def headless(self, name, *words):
        bag = os.path.join(self.folder, name + '.bag')
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'bag:=' + bag] + COMMON + list(words),
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=180)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        return bag

    def test_threads_and_split_controllers_record_identical_bags(self):
        bags = {'threads%d' % t: self.headless('threads%d' % t, 'threads:=%d' % t, *WORDS) for t in (1, 2, 3)}
        split = os.path.join(self.folder, 'split.bag')
        noise = '{%s}' % ', '.join('%s: {%s}' % (d, ', '.join('%s: %s' % kv for kv in sorted(v.items())))
                                   for d, v in sorted(NOISE.items()))
        graph = subprocess.run(['rosrun', 'swarm_forage', 'forage', '--launch', 'noise_split.launch', 'metrics:=false',
                                'wait_for_subscribers:=0',
                                'record:=true', 'bag:=' + split, 'threads:=2', 'noise:=' + noise] + COMMON,
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=180)
        self.assertEqual(graph.returncode, 0, graph.stdout[-3000:])
        bags['split graph'] = split
        runs = {name: messages(path) for name, path in bags.items()}
        first = runs['threads1']
        for name, run in runs.items():
            self.assertEqual(sorted(run), sorted(first), name)
            # Two controller ranges report their own swarm/status each tick where one range does headless;
            # the world's records (robots, blocks, performance, identity, end) must be the same bytes.
            for topic in sorted(t for t in first if not (name == 'split graph' and t == '/swarm/status')):
                self.assertEqual(len(run[topic]), len(first[topic]), '%s %s' % (name, topic))
                for k, (x, y) in enumerate(zip(first[topic], run[topic])):
                    self.assertEqual(x, y, '%s message %d differs between threads1 and %s' % (topic, k, name))
        # Two controller ranges answered in the split graph: the status has both.
        with open_bag(split) as bag:
            sources = {m.first_id for _, m, _ in bag.read_messages(topics=['/swarm/status'])}
            info = next(m for _, m, _ in bag.read_messages(topics=['/world/run_info']))
        self.assertEqual(sources, {0, 20})
        # The noise words come last but for the model's quirks (the default model has some).
        self.assertTrue(info.world_constants.split(' quirks=')[0].endswith(' ' + EXPECTED), info.world_constants)
        print('%d bags identical, %d messages each; identity words: %s'
              % (len(runs), sum(len(v) for v in first.values()), EXPECTED))
        # The control: the same run without noise is another run.
        quiet = messages(self.headless('quiet'))
        self.assertNotEqual(quiet['/world/robots'], first['/world/robots'])


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'noise_graph', NoiseGraph, sys.argv)
