#!/usr/bin/env python3
"""Population dynamics through the real nodes: with robots dying, being born, failing and being
repaired, run_experiment's bags for 1, 2 and 3 threads, the node graph's bag and the bag of a graph whose
robots are split over two controller_nodes are identical message for message; world/population is
recorded every tick and its counts add up."""
import os
import subprocess
import sys
import tempfile
import unittest

import rostest

from check_headless_identity import messages
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import open_bag, removed_at_exit

TICKS = 400
N = 40
RATES = ['population/death:=0.01', 'population/birth:=0.005', 'population/malfunction:=0.03',
         'population/repair:=0.02']
COMMON = ['n_robots:=%d' % N, 'ticks:=%d' % TICKS, 'seed:=5', 'controller:=dpo'] + RATES


def run(command, bag, *args):
    proc = subprocess.run(['rosrun', 'swarm_forage'] + command + ['bag:=' + bag] + COMMON + list(args),
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=180)
    return proc


class Population(unittest.TestCase):
    def setUp(self):
        self.folder = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_population_'))

    def bag(self, name):
        return os.path.join(self.folder, name + '.bag')

    def assert_same(self, a_path, b_path, what, ranges=1):
        """Every topic identical; with `ranges` controller ranges, swarm/status holds one record per range."""
        a, b = messages(a_path), messages(b_path)
        self.assertEqual(sorted(a), sorted(b), what + ': the bags record different topics')
        if ranges > 1:
            self.assertEqual(len(b.pop('/swarm/status')), ranges * len(a.pop('/swarm/status')), what)
        for topic in sorted(a):
            self.assertEqual(len(a[topic]), len(b[topic]), '%s: %s' % (what, topic))
            for k, (x, y) in enumerate(zip(a[topic], b[topic])):
                self.assertEqual(x, y, '%s: %s message %d differs' % (what, topic, k))

    def test_bags_identical_for_threads_graph_and_split_controllers(self):
        for threads in (1, 2, 3):
            proc = run(['run_experiment'], self.bag('threads%d' % threads), 'threads:=%d' % threads)
            self.assertEqual(proc.returncode, 0, proc.stdout[-3000:])
        self.check_population(self.bag('threads1'))
        for threads in (2, 3):
            self.assert_same(self.bag('threads1'), self.bag('threads%d' % threads), '%d threads' % threads)
        proc = run(['forage', 'metrics:=false', 'wait_for_subscribers:=0', 'record:=true'], self.bag('graph'))
        self.assertEqual(proc.returncode, 0, proc.stdout[-3000:])
        self.assert_same(self.bag('threads1'), self.bag('graph'), 'node graph')
        proc = run(['forage', '--launch', 'population_split.launch', 'metrics:=false', 'wait_for_subscribers:=0',
                    'record:=true'], self.bag('split'))
        self.assertEqual(proc.returncode, 0, proc.stdout[-3000:])
        self.assert_same(self.bag('threads1'), self.bag('split'), 'split controllers', ranges=2)

    def check_population(self, path):
        with open_bag(path) as bag:
            pops = [m for _, m, _ in bag.read_messages(topics=['/world/population'])]
            info = [m for _, m, _ in bag.read_messages(topics=['/world/run_info'])]
            perf = [m for _, m, _ in bag.read_messages(topics=['/world/performance'])]
        self.assertEqual([p.tick for p in pops], list(range(TICKS)), 'one world/population per tick')
        self.assertIn('population/death=0.01 population/birth=0.005 population/malfunction=0.03 '
                      'population/repair=0.02 population/max_size=%d' % N, info[0].world_constants)
        self.assertTrue(all(p.swarm_size == N for p in perf), 'swarm_size stays N')
        present, queue = N, []
        for p in pops:
            for robot in p.deaths:
                if robot in queue:
                    queue.remove(robot)
            present += len(p.births) - len(p.deaths)
            queue += list(p.malfunctions)
            for robot in p.repairs:
                self.assertEqual(robot, queue.pop(0), 'tick %d: the head of the repair queue rejoins' % p.tick)
            self.assertEqual((p.present, p.queue, p.active), (present, len(queue), present - len(queue)), p.tick)
            self.assertEqual(p.max_size, N)
        events = sum(len(p.deaths) + len(p.births) + len(p.malfunctions) + len(p.repairs) for p in pops)
        self.assertGreater(events, 10, 'the dynamics must act for the comparison to mean something')
        print('%d population events; at the end %d active, %d awaiting repair' % (events, pops[-1].active,
                                                                                 pops[-1].queue))

    def test_bad_population_parameters_are_refused_with_the_range(self):
        for words, message in ((['population/death:=-0.1'], '~population/death must be in [0, 1]'),
                               (['population/repair:=2'], '~population/repair must be in [0, 1]'),
                               (['population/max_size:=30', 'population/death:=0.01'],
                                'population/max_size must be the swarm size n_robots = 40')):
            proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'n_robots:=40', 'ticks:=10'] + words,
                                  stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=60)
            self.assertEqual(proc.returncode, 2, (words, proc.stdout))
            self.assertIn(message, proc.stdout, words)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'population', Population)
