#!/usr/bin/env python3
"""No run computed twice: `sweep --reuse DIR` hard-links the runs another sweep
folder holds complete instead of running them, says how many it found, and its tables equal those of
the same sweep computed from scratch; a record that is not whole is run again; a reused record stays
valid when the other folder is deleted; bad --reuse folders are refused (exit 2)."""
import glob
import os
import shutil
import sys
import tempfile
import unittest

import rostest
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import experiment_text, sweep  # noqa: E402

FIRST = experiment_text('first', [4], 600, 200)
# Another experiment: one more controller, and a GP-DPO parameter CRW and DPO do not read (as the paper's
# time-varying file has): its CRW and DPO runs are the first sweep's.
SECOND = FIRST.replace('name: first', 'name: second').replace('[crw, dpo]', '[crw, dpo, gp_dpo]') + \
    'params: {gp_dpo/estimates: time_varying}\n'


def bags(out):
    return sorted(glob.glob(os.path.join(out, 'runs', '*.bag')))


def table(out, name):
    with open(os.path.join(out, 'tables', name)) as f:
        return f.read()


class Reuse(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_reuse_'))
        cls.first, cls.fresh = os.path.join(cls.tmp, 'first'), os.path.join(cls.tmp, 'fresh')
        cls.second_file = write(cls.tmp, 'second.yaml', SECOND)
        for out, path in ((cls.first, write(cls.tmp, 'first.yaml', FIRST)), (cls.fresh, cls.second_file)):
            proc = cls.sweep(path, '--out', out, '-j', '2')
            assert proc.returncode == 0, proc.stdout

    sweep = staticmethod(sweep)

    def test_1_reused_runs_are_linked_not_rerun_and_the_tables_equal_a_fresh_sweep(self):
        out = os.path.join(self.tmp, 'second')
        dry = self.sweep(self.second_file, '--out', out, '--reuse', self.first, '--dry-run')
        self.assertEqual(dry.returncode, 0, dry.stdout)
        self.assertIn('reuse: 4 of the 6 runs to do found complete elsewhere (would be hard-linked); 4 in %s'
                      % self.first, dry.stdout)
        self.assertIn('plan: 6 runs: 0 done, 4 reused (found complete elsewhere), 2 to do', dry.stdout)
        self.assertFalse(os.path.exists(out), 'a dry run writes nothing')
        before = {os.path.basename(p): os.stat(p) for p in bags(self.first)}
        proc = self.sweep(self.second_file, '--out', out, '--reuse', self.first, '-j', '2')
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('reuse: 4 of the 6 runs to do found complete elsewhere (hard-linked, not rerun)', proc.stdout)
        self.assertIn('6 runs (0 done, 4 found elsewhere, 2 to do)', proc.stdout)
        linked = [p for p in bags(out) if not os.path.basename(p).startswith('gp_dpo')]
        self.assertEqual(len(linked), 4, bags(out))
        inodes = {(s.st_ino, s.st_mtime_ns) for s in before.values()}
        for p in linked:  # the same file (a hard link), not a new run
            self.assertIn((os.stat(p).st_ino, os.stat(p).st_mtime_ns), inodes, p)
            self.assertEqual(os.stat(p).st_nlink, 2, p)
        for name in ('series.csv', 'scalability.csv', 'self_organization.csv', 'bootstrap.csv'):
            self.assertEqual(table(out, name), table(self.fresh, name), name)
        # The only copy: the first folder gone, the reused records still count.
        shutil.rmtree(self.first + '_gone', ignore_errors=True)
        os.rename(self.first, self.first + '_gone')
        try:
            shutil.copytree(self.first + '_gone', self.first, copy_function=os.link)  # keep it for test 2
            shutil.rmtree(self.first + '_gone')
            os.remove(os.path.join(out, 'verified.tsv'))  # read every record again
            again = self.sweep(self.second_file, '--out', out)
            self.assertEqual(again.returncode, 0, again.stdout)
            self.assertIn('6 runs (6 done, 0 to do)', again.stdout)
            self.assertEqual(table(out, 'series.csv'), table(self.fresh, 'series.csv'))
        finally:
            if not os.path.isdir(self.first):
                os.rename(self.first + '_gone', self.first)

    def test_2_a_record_that_is_not_whole_is_run_again(self):
        broken = os.path.join(self.tmp, 'broken')
        shutil.copytree(self.first, broken)  # copies: truncating one leaves the first folder's alone
        victim = bags(broken)[0]
        with open(victim, 'r+b') as f:
            f.truncate(os.path.getsize(victim) // 2)
        os.remove(os.path.join(broken, 'verified.tsv'))
        out = os.path.join(self.tmp, 'second_broken')
        proc = self.sweep(self.second_file, '--out', out, '--reuse', broken, '-j', '2')
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('reuse: 3 of the 6 runs to do found complete elsewhere', proc.stdout)
        self.assertIn('1 found but not whole, run again', proc.stdout)
        self.assertIn('not reused (run instead): %s' % victim, proc.stdout)
        self.assertEqual(table(out, 'series.csv'), table(self.fresh, 'series.csv'))

    def test_4_a_record_of_an_edited_series_file_is_never_reused(self):
        """The series file enters the runs' identity by content: after one V changes, no record of the
        old file is found elsewhere, and each new record carries the new file's digest."""
        folder = os.path.join(self.tmp, 'series')
        os.makedirs(folder)
        profile = 't,V\n0,0.0\n40,0.5\n80,0.2\n'
        write(folder, 'prof.csv', profile)
        spec = write(folder, 'series.yaml', experiment_text('series', [4], 600, 200, controllers=('crw',)) +
                     'conditions:\n  - {waveform: series, series: prof.csv}\n')
        old, new = os.path.join(folder, 'old'), os.path.join(folder, 'new')
        self.assertEqual(self.sweep(spec, '--out', old, '-j', '2').returncode, 0)
        write(folder, 'prof.csv', profile.replace('40,0.5', '40,0.6'))
        proc = self.sweep(spec, '--out', new, '--reuse', old, '-j', '2')
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('reuse: 0 of the 2 runs to do found complete elsewhere', proc.stdout)
        self.assertIn('2 runs (0 done, 2 to do)', proc.stdout)
        olds, news = [os.path.basename(p) for p in bags(old)], [os.path.basename(p) for p in bags(new)]
        self.assertEqual(len(news), 2, news)
        self.assertFalse(set(olds) & set(news), 'an edited series gives other records')
        inodes = {os.stat(p).st_ino for p in bags(old)}
        self.assertFalse(inodes & {os.stat(p).st_ino for p in bags(new)}, 'no record of the old file is linked')

    def test_3_bad_reuse_folders_are_refused(self):
        out = os.path.join(self.tmp, 'bad')
        for folder, message in ((os.path.join(self.tmp, 'nowhere'), 'is not a sweep folder'),
                                (self.tmp, 'is not a sweep folder'), (out, 'is this sweep\'s own --out folder')):
            if folder == out:
                shutil.copytree(self.first, out, copy_function=os.link)
            proc = self.sweep(self.second_file, '--out', out, '--reuse', folder)
            self.assertEqual(proc.returncode, 2, proc.stdout)
            self.assertIn(message, proc.stdout)
        proc = self.sweep(self.second_file, '--out', out, '--planned', os.path.join(self.tmp, 'x.tsv'))
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('--planned and --plan-file go with --dry-run', proc.stdout)
        # The sweep's other options: SLURM time limits and checkpoints.
        for extra, message in ((['--time', '5'], '--time goes with --slurm'),
                               (['--slurm', '--time', '0:30'], 'is under a minute'),
                               (['--slurm', '--time', 'soon'], "--time 'soon' is not a SLURM time"),
                               (['--checkpoint-every', '-1'], '--checkpoint-every must be >= 0 ticks')):
            proc = self.sweep(self.second_file, '--out', out, *extra)
            self.assertEqual(proc.returncode, 2, proc.stdout)
            self.assertIn(message, proc.stdout)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'sweep_reuse', Reuse)
