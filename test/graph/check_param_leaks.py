#!/usr/bin/env python3
"""Parameters never leak from one run to the next on a long-lived master: a run with noise, then a plain one,
gives a plain run (its identity and name without noise); a typo'd noise key or constant fails that run only;
the nodes leave none of their parameters behind, so a world_node started by hand after a recorded run never
writes (or overwrites) that run's bag."""
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospy
import rostest

TINY = ['n_robots:=4', 'ticks:=50', 'metrics:=false', 'wait_for_subscribers:=0']
NODES = ('world', 'controller', 'environment', 'metrics')


def forage(*args):
    return subprocess.run(['rosrun', 'swarm_forage', 'forage'] + TINY + list(args), stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=300)


def run_info(path):
    with rosbag.Bag(path) as bag:
        infos = [m for _, m, _ in bag.read_messages(topics=['/world/run_info'])]
    assert len(infos) == 1, '%s holds %d run_info messages' % (path, len(infos))
    return infos[0]


def digest(path):
    with open(path, 'rb') as f:
        return hashlib.sha1(f.read()).hexdigest()


class ParamLeaks(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node('check_param_leaks', anonymous=True)

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_param_leaks_')

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def path(self, name):
        return os.path.join(self.tmp, name)

    def assertNoNodeParams(self, after):
        left = [n for n in rospy.get_param_names() if n.split('/')[1] in NODES]
        self.assertEqual(left, [], 'parameters left on the master after %s' % after)

    def test_1_noise_then_a_plain_run(self):
        noisy, plain = self.path('noisy.bag'), self.path('plain.bag')
        r = forage('record:=true', 'bag:=' + noisy, 'noise:={light: {level: 0.05}}')
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertIn('noise/light=gaussian:0.05', run_info(noisy).world_constants)
        r = forage('record:=true', 'bag:=' + plain)
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        info = run_info(plain)
        self.assertNotIn('noise', info.world_constants)
        self.assertNotEqual(info.identity, run_info(noisy).identity)
        # The same plain run named by its identity: no noise in its name or identity either.
        lib = self.path('lib')
        r = forage('record:=true', 'results:=' + lib)
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        (name,) = os.listdir(lib)
        self.assertTrue(name.endswith('_%s.bag' % info.identity), name)
        self.assertNoNodeParams('the runs')

    def test_2_a_typo_fails_only_its_own_run(self):
        for bad, words in (('noise:={lite: {level: 0.05}}', '~noise/lite/level (/world/noise/lite/level) is not a '
                                                             'parameter of world_node'),
                           ('controller_constants:={crw: {wander_forse: 9.0}}', '~crw/wander_forse is not a crw '
                                                                                'constant')):
            r = forage(bad)
            self.assertEqual(r.returncode, 2, r.stdout[-3000:])
            self.assertIn(words, r.stdout)
            r = forage('record:=true', 'results:=' + self.path('after'))
            self.assertEqual(r.returncode, 0, 'the run after %s:\n%s' % (bad, r.stdout[-3000:]))
            self.assertNoNodeParams('%s and a good run' % bad)

    def test_3_a_world_node_started_by_hand_never_writes_an_earlier_bag(self):
        bag = self.path('run.bag')
        r = forage('record:=true', 'bag:=' + bag, 'overwrite:=true', 'seed:=5')
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        before = digest(bag)
        # Parameters a hand set for one node do not outlive it either.
        rospy.set_param('/world/bag', self.path('hand.bag'))
        peers = [subprocess.Popen(['rosrun', 'swarm_forage', node] + args, stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True)
                 for node, args in (('controller_node', []), ('environment_node', ['_ticks:=50']))]
        try:
            first = subprocess.run(['rosrun', 'swarm_forage', 'world_node', '_n_robots:=4', '_ticks:=50',
                                    '_exit_when_done:=true'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                   text=True, timeout=300)
            self.assertEqual(first.returncode, 0, first.stdout[-3000:])
            self.assertTrue(os.path.isfile(self.path('hand.bag')), first.stdout[-3000:])
            # No bag argument now: nothing is recorded, the earlier bags are untouched.
            second = subprocess.run(['rosrun', 'swarm_forage', 'world_node', '_n_robots:=4', '_ticks:=50',
                                     '_exit_when_done:=true'], stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                                    text=True, timeout=300)
            self.assertEqual(second.returncode, 0, second.stdout[-3000:])
        finally:
            for p in peers:
                p.terminate()
                p.communicate(timeout=60)
        self.assertEqual(digest(bag), before, 'a world_node started by hand rewrote the earlier bag')
        self.assertEqual(run_info(bag).seed, 5)
        self.assertEqual(sorted(os.listdir(self.tmp)), ['hand.bag', 'run.bag'])
        self.assertNoNodeParams('the nodes started by hand')


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'check_param_leaks', ParamLeaks, sys.argv)
