#!/usr/bin/env python3
"""A Python controller in process (docs/python-controllers.md) records bit-identical bags headless with one
or two threads, in the node graph and in the nodelet graph (headless against the graph but for header.seq);
a run stopped after a checkpoint and resumed, and a run forked from a saved state, record the bag of the run
that never stopped; the run's constants carry the digest of the class and its module's source."""
import os
import sys

import rosbag
import rospkg
import rostest

SWARM_FORAGE = rospkg.RosPack().get_path('swarm_forage')
sys.path[:0] = [os.path.join(SWARM_FORAGE, 'test', 'helpers'), os.path.join(SWARM_FORAGE, 'test', 'graph')]
from run_helpers import RUN, RunsCase, run, stop_after_checkpoint  # noqa: E402

KIND = 'swarm_forage_examples/numpy_crw'
TARGET = 'swarm_forage_examples.numpy_crw.NumpyCrw'


def fnv1a(data, h=2166136261):
    for byte in data:
        h = ((h ^ byte) * 16777619) & 0xffffffff
    return h


class PythonModes(RunsCase):
    PREFIX = 'swarm_forage_python_modes_'

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
        self.assertModesAgree(headless, words, KIND)
        # Another constant is another run.
        other = self.bag('other', *RUN, KIND + '/wander_step_deg:=4', *words)
        self.assertOtherRun(headless, other)

    def test_stopped_and_resumed_run_records_the_uninterrupted_bag(self):
        words = ['controller:=' + KIND, 'n_robots:=64', 'ticks:=3000', 'seed:=4', 'record_every:=500']
        whole = self.bag('whole', *RUN, *words)
        bag, ckpt = self.path('t.bag'), self.path('t.bag.checkpoint')
        args = words + ['bag:=' + bag, 'checkpoint_every:=300']
        stop_after_checkpoint(self, args)
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
