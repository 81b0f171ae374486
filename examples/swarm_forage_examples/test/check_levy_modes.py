#!/usr/bin/env python3
"""The Levy walker (src/levy.cpp) records bit-identical bags headless with one or two threads (its range
stepped in parts), in the node graph and in the nodelet graph: its randomness is a pure function of
(seed, robot, tick). Any split of the range gives the same commands: test_levy.cpp."""
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospkg
import rostest

sys.path.insert(0, os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'test', 'graph'))
from check_headless_identity import messages  # noqa: E402  (header.seq cleared: a graph's differs)

LEVY = 'swarm_forage_examples/levy'
GRAPH = ['metrics:=false', 'wait_for_subscribers:=0', 'record:=true']


def run(*cmd, timeout=400):
    proc = subprocess.run(list(cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)
    return proc.returncode, proc.stdout


class LevyModes(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_levy_modes_')
        self.addCleanup(shutil.rmtree, self.tmp, True)

    def bag(self, name, *cmd):
        path = os.path.join(self.tmp, name + '.bag')
        code, out = run(*(list(cmd) + ['bag:=' + path]))
        self.assertEqual(code, 0, out[-3000:])
        return path

    def assertSameRun(self, a, b):
        code, out = run('rosrun', 'swarm_forage', 'compare_bags', a, b, '--ignore', '/world/provenance')
        self.assertEqual(code, 0, out)
        self.assertIn('identical', out)

    def test_headless_threads_graph_split_and_nodelets_agree(self):
        words = ['controller:=' + LEVY, 'n_robots:=24', 'seed:=5', 'ticks:=4000']
        headless = self.bag('headless', 'rosrun', 'swarm_forage', 'run_experiment', 'threads:=1', *words)
        with rosbag.Bag(headless) as bag:
            status = next(m for _, m, _ in bag.read_messages(topics=['/swarm/status']))
            carried = max(m.carrying for _, m, _ in bag.read_messages(topics=['/world/performance']))
        self.assertEqual(status.controller, LEVY)
        self.assertIn(LEVY + '/mu=2 ', status.constants)
        self.assertGreater(carried, 0, 'the walker picked up nothing')
        graph = self.bag('graph', 'rosrun', 'swarm_forage', 'forage', *(GRAPH + words))
        nodelet = self.bag('nodelet', 'rosrun', 'swarm_forage', 'forage', 'nodelet:=true', *(GRAPH + words))
        self.assertSameRun(graph, nodelet)
        a, b = messages(headless), messages(graph)
        del a['/world/provenance'], b['/world/provenance']
        self.assertEqual(sorted(a), sorted(b))
        for topic in a:
            self.assertEqual(a[topic], b[topic], topic)
        # A range of 1,100 robots is stepped in parts on worker threads (512 robots or more a part).
        big = ['controller:=' + LEVY, 'n_robots:=1100', 'seed:=2', 'ticks:=300']
        one = self.bag('one_thread', 'rosrun', 'swarm_forage', 'run_experiment', 'threads:=1', *big)
        two = self.bag('two_threads', 'rosrun', 'swarm_forage', 'run_experiment', 'threads:=2', *big)
        self.assertSameRun(one, two)
        # The test can fail: another mu is another run.
        other = self.bag('other_mu', 'rosrun', 'swarm_forage', 'run_experiment', 'threads:=1', LEVY + '/mu:=1.5',
                         *words)
        code, out = run('rosrun', 'swarm_forage', 'compare_bags', headless, other, '--ignore', '/world/provenance')
        self.assertEqual(code, 1, out)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'levy_modes', LevyModes)
