#!/usr/bin/env python3
"""A disk that fills (a tmpfs of a few hundred KiB): a run ends with exit 1 and an outcome naming the
folder, what was lost and the space free, never SIGABRT, and keeps no partial file; a sweep stops with a
message naming its folder, leaves no partial file of its own, and once space is freed the same command
continues and completes."""
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from root_only import needs_root, rosrun  # noqa: E402
from graph_helpers import removed_at_exit
from sweep_helpers import experiment_text, sweep


def mount(path, size):
    """A tmpfs of `size` at `path` (root only: the test says so rather than pass without a full disk)."""
    proc = subprocess.run(['mount', '-t', 'tmpfs', '-o', 'size=' + size, 'tmpfs', path],
                          stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if proc.returncode != 0:
        raise AssertionError('this test fills a tmpfs and needs root to mount one: ' + proc.stdout.strip())


@needs_root('mounting the tmpfs this test fills')
class DiskFull(unittest.TestCase):
    def setUp(self):
        self.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_disk_full_'))
        self.full = os.path.join(self.tmp, 'full')
        os.mkdir(self.full)
        mount(self.full, '600k')

    def tearDown(self):
        subprocess.run(['umount', self.full])
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_1_a_run_ends_with_its_reason_and_keeps_nothing_partial(self):
        outcome = os.path.join(self.tmp, 'outcome.yaml')
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', 'controller:=crw', 'arena:=32x16',
                               'n_robots:=16', 'ticks:=20000', 'seed:=1', 'compression:=none',
                               'bag:=' + os.path.join(self.full, 'run.bag'), 'outcome:=' + outcome],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
        self.assertEqual(proc.returncode, 1, proc.stdout[-3000:])
        self.assertIn('No space left on device', proc.stdout)
        self.assertIn(' free in ' + self.full, proc.stdout)
        with open(outcome) as f:
            said = yaml.safe_load(f)
        self.assertIn('No space left on device', str(said))
        self.assertIn('the record was not kept', str(said))
        self.assertEqual(os.listdir(self.full), [])  # no partial record, no .active part

    def test_2_a_sweep_stops_naming_its_folder_and_continues_once_space_is_freed(self):
        spec = os.path.join(self.tmp, 'full.yaml')
        with open(spec, 'w') as f:
            f.write(experiment_text('full', [8], 3000, 500, controllers=('crw',), runs=3))
        out = os.path.join(self.full, 'sweep')
        proc = sweep(spec, '--out', out, '--jobs', '1', '--compression', 'none')
        self.assertEqual(proc.returncode, 1, proc.stdout[-3000:])
        self.assertIn('no space left on the device of ' + out, proc.stdout)
        self.assertIn('run the same command again', proc.stdout)
        self.assertNotIn('Traceback', proc.stdout)
        self.assertEqual(glob.glob(os.path.join(out, '**', '*.active'), recursive=True), [])
        self.assertEqual(glob.glob(os.path.join(out, 'verified.tsv.*')), [])
        kept = glob.glob(os.path.join(out, 'runs', '*.bag'))
        self.assertLess(len(kept), 3, kept)
        subprocess.run(['mount', '-o', 'remount,size=64m', self.full], check=True)
        proc = sweep(spec, '--out', out, '--jobs', '1', '--compression', 'none')
        self.assertEqual(proc.returncode, 0, proc.stdout[-3000:])
        self.assertIn('%d done' % len(kept), proc.stdout)  # the runs recorded before the disk filled are kept
        self.assertIn('full complete: 3 runs', proc.stdout)


if __name__ == '__main__':
    rosrun('swarm_forage', 'disk_full', DiskFull)
