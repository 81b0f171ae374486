#!/usr/bin/env python3
"""A Python controller in process (docs/python-controllers.md) records bit-identical bags headless with one
or two threads, in the node graph and in the nodelet graph (headless against the graph but for header.seq);
a run stopped after a checkpoint and resumed, and a run forked from a saved state, record the bag of the run
that never stopped; the run's constants carry the digest of the class and its module's source."""
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospkg
import rostest

sys.path.insert(0, os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'test', 'graph'))
from check_headless_identity import messages  # noqa: E402  (header.seq cleared: a graph's differs)

KIND = 'swarm_forage_examples/numpy_crw'
TARGET = 'swarm_forage_examples.numpy_crw.NumpyCrw'
GRAPH = ['metrics:=false', 'wait_for_subscribers:=0', 'record:=true']
RUN = ['rosrun', 'swarm_forage', 'run_experiment']


def run(*cmd, timeout=600):
    proc = subprocess.run(list(cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)
    return proc.returncode, proc.stdout


def fnv1a(data, h=2166136261):
    for byte in data:
        h = ((h ^ byte) * 16777619) & 0xffffffff
    return h


class PythonModes(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_python_modes_')
        self.addCleanup(shutil.rmtree, self.tmp, True)

    def path(self, name):
        return os.path.join(self.tmp, name)

    def bag(self, name, *cmd):
        path = self.path(name + '.bag')
        code, out = run(*(list(cmd) + ['bag:=' + path]))
        self.assertEqual(code, 0, out[-3000:])
        return path

    def assertSameRun(self, a, b):
        code, out = run('rosrun', 'swarm_forage', 'compare_bags', a, b, '--ignore', '/world/provenance')
        self.assertEqual(code, 0, out)
        self.assertIn('identical', out)

    def test_headless_threads_graph_and_nodelets_agree(self):
        words = ['controller:=' + KIND, 'n_robots:=24', 'seed:=5', 'ticks:=3000']
        headless = self.bag('headless', *RUN, 'threads:=1', *words)
        with rosbag.Bag(headless) as bag:
            status = next(m for _, m, _ in bag.read_messages(topics=['/swarm/status']))
            delivered = max(m.cumulative for _, m, _ in bag.read_messages(topics=['/world/performance']))
        self.assertEqual(status.controller, KIND)
        self.assertEqual(list(status.state_names),
                         ['explore', 'pickup', 'transport', 'nest_wander', 'drop', 'leave_nest'])
        with open(os.path.join(rospkg.RosPack().get_path('swarm_forage_examples'), 'src', 'swarm_forage_examples',
                               'numpy_crw.py'), 'rb') as f:
            digest = fnv1a(f.read(), fnv1a((TARGET + '\n').encode())) & 0x7fffffff
        self.assertIn('%s/source_digest=%d' % (KIND, digest), status.constants)
        self.assertGreater(delivered, 0, 'the numpy CRW delivered nothing')
        graph = self.bag('graph', 'rosrun', 'swarm_forage', 'forage', *(GRAPH + words))
        nodelet = self.bag('nodelet', 'rosrun', 'swarm_forage', 'forage', 'nodelet:=true', *(GRAPH + words))
        self.assertSameRun(graph, nodelet)
        a, b = messages(headless), messages(graph)
        del a['/world/provenance'], b['/world/provenance']
        self.assertEqual(sorted(a), sorted(b))
        for topic in a:
            self.assertEqual(a[topic], b[topic], topic)
        big = ['controller:=' + KIND, 'n_robots:=1100', 'seed:=2', 'ticks:=300']
        one = self.bag('one_thread', *RUN, 'threads:=1', *big)
        two = self.bag('two_threads', *RUN, 'threads:=2', *big)
        self.assertSameRun(one, two)
        # Another constant is another run.
        other = self.bag('other', *RUN, KIND + '/wander_step_deg:=4', *words)
        code, out = run('rosrun', 'swarm_forage', 'compare_bags', headless, other, '--ignore', '/world/provenance')
        self.assertEqual(code, 1, out)

    def test_stopped_and_resumed_run_records_the_uninterrupted_bag(self):
        words = ['controller:=' + KIND, 'n_robots:=64', 'ticks:=3000', 'seed:=4', 'record_every:=500']
        whole = self.bag('whole', *RUN, *words)
        bag, ckpt = self.path('t.bag'), self.path('t.bag.checkpoint')
        args = words + ['bag:=' + bag, 'checkpoint_every:=300']
        p = subprocess.Popen(RUN + args + ['progress:=1'], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        for line in p.stderr:
            if 'tick 301 of' in line:  # the checkpoint of tick 300 is written
                break
        p.send_signal(signal.SIGTERM)
        rest = p.stderr.read()
        self.assertEqual(p.wait(), 1, rest[-2000:])
        self.assertIn('resume:=%s continues it' % ckpt, rest)
        code, out = run(*(RUN + args + ['resume:=' + ckpt]))
        self.assertEqual(code, 0, out)
        self.assertSameRun(whole, bag)

    def test_fork_from_a_saved_state_equals_a_fresh_run(self):
        words = ['controller:=' + KIND, 'n_robots:=32', 'ticks:=2000', 'seed:=3']
        step = ['waveform:=step_up', 'beta:=0.5', 'alpha:=200']
        save = self.path('ideal_at_1000.ckpt')
        code, out = run(*(RUN + words + ['bag_dir:=' + self.path('ideal'), 'save_at:=1000', 'save:=' + save]))
        self.assertEqual(code, 0, out)
        code, out = run(*(RUN + words + step + ['bag_dir:=' + self.path('fresh')]))
        self.assertEqual(code, 0, out)
        code, out = run(*(RUN + words + step + ['bag_dir:=' + self.path('fork'), 'resume:=' + save]))
        self.assertEqual(code, 0, out)
        self.assertEqual(os.listdir(self.path('fork')), os.listdir(self.path('fresh')))
        code, out = run('rosrun', 'swarm_forage', 'compare_bags', self.path('fresh'), self.path('fork'))
        self.assertEqual(code, 0, out)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'python_modes', PythonModes)
