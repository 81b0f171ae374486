#!/usr/bin/env python3
"""The results table of both models (swarm_forage.models_table), made from the studies' verdicts.json: the
README holds the committed studies' table; a later study's verdict on a claim replaces an earlier one's, an
undecided claim names the seeds that would decide it, and a study without verdicts or a file without the
markers is refused by name."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from tmp_files import removed_at_exit, write

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOL = os.path.join(ROOT, 'scripts', 'models_table')


def run(args, cwd=ROOT):
    return subprocess.run([sys.executable, TOOL] + args, cwd=cwd, capture_output=True, text=True)


def verdict(claim, verdict, margin, seeds, needed=None):
    return {'claim': claim, 'verdict': verdict, 'quantity': 'q', 'op': '<=', 'threshold': 0.15, 'margin': margin,
            'low': None if margin is None else margin - 0.05, 'high': None if margin is None else margin + 0.05, 'seeds': seeds, 'seeds_needed': needed, 'groups': []}


class ModelsTable(unittest.TestCase):
    def setUp(self):
        self.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_models_table_'))

    def study(self, name, verdicts):
        os.makedirs(os.path.join(self.tmp, name), exist_ok=True)
        write(self.tmp, os.path.join(name, 'verdicts.json'), json.dumps(verdicts))
        return os.path.join(self.tmp, name)

    def test_1_the_readme_holds_the_committed_studies_table(self):
        proc = run(['--default', 'docs/paper_quick', 'docs/paper_96', '--corrected', 'docs/paper_quick_swarm_forage',
                    'docs/paper_96_swarm_forage', '--check', 'README.md'])
        self.assertEqual(proc.returncode, 0, proc.stdout + proc.stderr)

    def test_2_a_later_study_decides_and_undecided_names_seeds(self):
        quick = self.study('quick', [verdict('d', 'not measured', None, []), verdict('c', 'disagrees', -0.1, [3])])
        arm = self.study('arm', [verdict('c', 'agrees', 0.11, [10]), verdict('d', 'undecided', 0.11, [10], 17)])
        other = self.study('other', [verdict('d', 'disagrees', 0.59, [10])])
        proc = run(['--default', quick, arm, '--corrected', other])
        self.assertEqual(proc.returncode, 0, proc.stderr)
        rows = {line.split(' | ')[0]: line for line in proc.stdout.splitlines()}
        self.assertIn('**agrees**: q 0.110 [0.060, 0.160], 10 seeds', rows['| (c)'])
        self.assertIn('undecided: q 0.110 [0.060, 0.160], 10 seeds (≈ 17 would decide)', rows['| (d)'])
        self.assertIn('disagrees: q 0.590', rows['| (d)'])
        self.assertIn('not measured', rows['| (a1)'])

    def test_3_bad_input_is_named(self):
        proc = run(['--default', self.tmp, '--corrected', self.tmp])
        self.assertNotEqual(proc.returncode, 0)
        self.assertIn('%s has no verdicts.json' % self.tmp, proc.stderr)
        study = self.study('s', [verdict('a1', 'agrees', 0.5, [3])])
        readme = write(self.tmp, 'README.md', '# no markers\n')
        proc = run(['--default', study, '--corrected', study, '--check', readme])
        self.assertEqual(proc.returncode, 1)
        self.assertIn('no <!-- models_table: begin -->', proc.stderr)
        write(self.tmp, 'README.md', 'a\n<!-- models_table: begin -->\nold\n<!-- models_table: end -->\nb\n')
        proc = run(['--default', study, '--corrected', study, '--check', readme])
        self.assertEqual(proc.returncode, 1)
        self.assertIn('is not what the committed verdicts say', proc.stderr)
        self.assertEqual(run(['--default', study, '--corrected', study, '--write', readme]).returncode, 0)
        self.assertEqual(run(['--default', study, '--corrected', study, '--check', readme]).returncode, 0)
        with open(readme) as f:
            text = f.read()
        self.assertTrue(text.startswith('a\n') and text.endswith('\nb\n'), text)


if __name__ == '__main__':
    unittest.main()
