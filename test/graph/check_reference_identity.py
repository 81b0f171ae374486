#!/usr/bin/env python3
"""The reference runs of rosbags/ (the default model) and rosbags/swarm_forage/ (the corrected model),
recorded again by today's code, are message-for-message the bags there (and give the same
expected_metrics.yaml): the proof that a refactor moved code, not behaviour. compare_bags itself is checked
to tell two different runs apart."""
import os
import subprocess
import sys
import tempfile
import unittest

import rospkg
import rostest
import yaml
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit

PACKAGE = rospkg.RosPack().get_path('swarm_forage')
REFS = os.path.join(PACKAGE, 'rosbags')


def compare(a, b):
    return subprocess.run(['rosrun', 'swarm_forage', 'compare_bags', a, b, '--ignore', '/world/provenance'],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, universal_newlines=True)


class ReferenceIdentity(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.fresh = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_refs_'))
        subprocess.run(['rosrun', 'swarm_forage', 'make_reference_bags', '--out', cls.fresh], check=True,
                       stdout=subprocess.DEVNULL)
        cls.corrected = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_refs_corrected_'))
        subprocess.run(['rosrun', 'swarm_forage', 'make_reference_bags', '--model', 'swarm_forage',
                        '--out', cls.corrected], check=True, stdout=subprocess.DEVNULL)

    def test_1_bags_are_identical(self):
        done = compare(REFS, self.fresh)
        self.assertEqual(done.returncode, 0, done.stdout)
        self.assertEqual(done.stdout.count('identical'), 5, done.stdout)

    def test_2_expected_metrics_are_identical(self):
        with open(os.path.join(REFS, 'expected_metrics.yaml')) as a, \
                open(os.path.join(self.fresh, 'expected_metrics.yaml')) as b:
            self.assertEqual(yaml.safe_load(a), yaml.safe_load(b))

    def test_4_the_corrected_model_keeps_its_runs(self):
        """model: swarm_forage gives the runs it gave as the default, bit for bit (its records' provenance
        names the model version and the code)."""
        kept = os.path.join(REFS, 'swarm_forage')
        done = compare(kept, self.corrected)
        self.assertEqual(done.returncode, 0, done.stdout)
        self.assertEqual(done.stdout.count('identical'), 5, done.stdout)
        with open(os.path.join(kept, 'expected_metrics.yaml')) as a, \
                open(os.path.join(self.corrected, 'expected_metrics.yaml')) as b:
            self.assertEqual(yaml.safe_load(a), yaml.safe_load(b))

    def test_3_compare_bags_tells_runs_apart(self):
        done = compare(os.path.join(REFS, 'crw_32x16_n16_null.bag'), os.path.join(self.fresh, 'crw_32x16_n8_null.bag'))
        self.assertEqual(done.returncode, 1, done.stdout)
        self.assertIn('differs in content', done.stdout)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'reference_identity', ReferenceIdentity)
