#!/usr/bin/env python3
"""Checkpoints of run_experiment (docs/runs-and-bags.md): a run killed after a checkpoint and
resumed records the bag of the run that never stopped (compare_bags); a kill in the middle of a checkpoint
write leaves the previous checkpoint usable; a run stopped by SIGTERM leaves its record in the bag segments
its checkpoint names (no NAME_incomplete.bag), a changed segment is refused, and the resumed run leaves
NAME.bag only; a step_up run forked from the ideal run's checkpoint at alpha records the bag of the same run
made from tick 0; bad parameters and files are refused with exit code 2."""
import os
import signal
import struct
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rostest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit
from run_helpers import stop_after_checkpoint

RUN = ['rosrun', 'swarm_forage', 'run_experiment']
COMPARE = ['rosrun', 'swarm_forage', 'compare_bags']


def run(*words, env=None, timeout=600):
    return subprocess.run(RUN + list(words), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          timeout=timeout, env=env)


def chunk_compressions(path):
    with rosbag.Bag(path) as bag:
        return {h.compression for h in bag._chunk_headers.values()}


def chunk_region(path):
    """A bag's chunk and index records, as its file holds them: from the file header to the index section."""
    with rosbag.Bag(path) as bag:
        start, end = bag._file_header_pos, bag._index_data_pos
    with open(path, 'rb') as f:
        data = f.read()
    (header_len,) = struct.unpack_from('<I', data, start)
    (data_len,) = struct.unpack_from('<I', data, start + 4 + header_len)
    return data[start + 8 + header_len + data_len:end]


class Checkpoint(unittest.TestCase):
    def setUp(self):
        self.folder = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_checkpoint_'))

    def path(self, name):
        return os.path.join(self.folder, name)

    def assertSameBags(self, a, b):
        compared = subprocess.run(COMPARE + [a, b], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.assertEqual(compared.returncode, 0, compared.stdout)
        self.assertIn('identical', compared.stdout)
        print(compared.stdout.strip())

    def test_killed_mid_write_resumes_from_the_previous_checkpoint(self):
        # The hook kills the run (SIGKILL) after 4096 bytes of its second checkpoint, tick 1000: the file of
        # tick 500 must still be whole, and the run resumed from it must record the uninterrupted bag.
        words = ['controller:=dpo', 'n_robots:=256', 'ticks:=2500', 'seed:=5', 'record_every:=100']
        whole = run(*(words + ['bag:=' + self.path('whole.bag')]))
        self.assertEqual(whole.returncode, 0, whole.stdout)
        bag, ckpt, outcome = self.path('killed.bag'), self.path('killed.bag.checkpoint'), self.path('outcome.yaml')
        env = dict(os.environ, SWARM_FORAGE_CHECKPOINT_DIE_AFTER='4096')
        killed = run(*(words + ['bag:=' + bag, 'checkpoint_every:=500']), env=env)
        self.assertEqual(killed.returncode, -signal.SIGKILL, killed.stdout)
        self.assertTrue(os.path.exists(ckpt), 'the first checkpoint is gone')
        self.assertEqual(os.path.getsize(ckpt + '.tmp'), 4096, 'the second write was not cut where the test said')
        self.assertFalse(os.path.exists(bag))
        resumed = run(*(words + ['bag:=' + bag, 'checkpoint_every:=500', 'resume:=' + ckpt, 'outcome:=' + outcome,
                                 'progress:=500']))
        self.assertEqual(resumed.returncode, 0, resumed.stdout)
        self.assertSameBags(self.path('whole.bag'), bag)
        # Progress counts from the checkpoint, the outcome is the whole run's, the killed writer's files are gone.
        self.assertIn('tick 1000 of 2500', resumed.stdout)
        self.assertNotIn('tick 500 of', resumed.stdout)
        with open(outcome) as f:
            record = f.read()
        self.assertIn('complete: true, ticks_done: 2500, ticks: 2500', record)
        # The killed writer's temporary bag and its segment of tick 1000 (no checkpoint names it) are gone, and
        # so are the segments the finished record joined.
        self.assertEqual([f for f in os.listdir(self.folder) if f.endswith(('.active', '.segment', '_incomplete.bag'))],
                         [])

    def test_killed_run_resumes_bit_identical(self):
        # A SIGKILL from outside, once a checkpoint exists: the run must still be running then (the test fails
        # rather than passing by luck if it had finished).
        words = ['controller:=crw', 'n_robots:=512', 'ticks:=6000', 'seed:=2', 'compression:=lz4']
        whole = run(*(words + ['bag:=' + self.path('whole.bag')]))
        self.assertEqual(whole.returncode, 0, whole.stdout)
        bag, ckpt = self.path('b.bag'), self.path('b.ckpt')
        args = words + ['bag:=' + bag, 'checkpoint_every:=200', 'checkpoint:=' + ckpt]
        p = subprocess.Popen(RUN + args, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        while not os.path.exists(ckpt) and p.poll() is None:
            time.sleep(0.01)
        p.send_signal(signal.SIGKILL)
        self.assertEqual(p.wait(), -signal.SIGKILL, 'the run ended before it could be killed')
        resumed = run(*(args + ['resume:=' + ckpt]))
        self.assertEqual(resumed.returncode, 0, resumed.stdout)
        self.assertSameBags(self.path('whole.bag'), bag)

    def test_stopped_run_leaves_its_record_to_the_checkpoint(self):
        # SIGTERM (a SLURM time limit) once a checkpoint exists: the run writes one more at the tick it stops and
        # leaves its record in the segments the checkpoint names, with no NAME_incomplete.bag; a changed segment is
        # refused and nothing removed; the resumed run records the uninterrupted bag and leaves nothing else.
        words = ['controller:=crw', 'n_robots:=256', 'ticks:=4000', 'seed:=4', 'compression:=bz2',
                 'record_every:=500']
        whole = run(*(words + ['bag:=' + self.path('whole.bag')]))
        self.assertEqual(whole.returncode, 0, whole.stdout)
        bag, ckpt = self.path('t.bag'), self.path('t.bag.checkpoint')
        args = words + ['bag:=' + bag, 'checkpoint_every:=300']
        stop_after_checkpoint(self, args)
        names = os.listdir(self.folder)
        self.assertEqual([n for n in names if n.startswith('t') and n.endswith(('.bag', '.active'))], [], names)
        segments = sorted(n for n in names if n.endswith('.segment'))
        self.assertGreaterEqual(len(segments), 2, names)  # tick 300's and the stop's
        # The parts are compressed as the record is: the join copies their chunks, bytes as they are.
        for name in segments:
            self.assertEqual(chunk_compressions(self.path(name)), {'bz2'}, name)
        copied = [chunk_region(self.path(name)) for name in segments[1:]]  # the first holds the provenance
        seg = self.path(segments[0])
        with open(seg, 'rb') as f:
            good = f.read()
        with open(seg, 'wb') as f:
            f.write(good[:-1])
        refused = run(*(args + ['resume:=' + ckpt]))
        self.assertEqual(refused.returncode, 2, refused.stdout)
        self.assertIn('its bag segment %s has %d bytes where the checkpoint says %d' % (seg, len(good) - 1, len(good)),
                      refused.stdout)
        self.assertEqual(sorted(n for n in os.listdir(self.folder) if n.endswith('.segment')), segments)
        with open(seg, 'wb') as f:
            f.write(good)
        resumed = run(*(args + ['resume:=' + ckpt]))
        self.assertEqual(resumed.returncode, 0, resumed.stdout)
        self.assertSameBags(self.path('whole.bag'), bag)
        with open(bag, 'rb') as f:
            joined = f.read()
        for name, region in zip(segments[1:], copied):
            self.assertIn(region, joined, '%s: its chunks were not copied' % name)
        self.assertEqual(chunk_compressions(bag), {'bz2'})
        self.assertEqual(chunk_compressions(self.path('whole.bag')), {'bz2'})
        self.assertEqual(sorted(os.listdir(self.folder)), ['t.bag', 't.bag.checkpoint', 'whole.bag'])

    def test_fork_equals_a_fresh_run(self):
        # The ideal run saved after tick 1000; step_up at alpha = 200 s (tick 1000 at 5 ticks/s) forked from
        # it, in a bag_dir (named by its identity), equals the step_up run made from tick 0.
        words = ['controller:=gp_dpo', 'n_robots:=64', 'ticks:=2000', 'seed:=3']
        step = ['waveform:=step_up', 'beta:=0.5', 'alpha:=200']
        save = self.path('ideal_at_1000.ckpt')
        ideal = run(*(words + ['bag_dir:=' + self.path('ideal'), 'save_at:=1000', 'save:=' + save]))
        self.assertEqual(ideal.returncode, 0, ideal.stdout)
        fresh = run(*(words + step + ['bag_dir:=' + self.path('fresh')]))
        self.assertEqual(fresh.returncode, 0, fresh.stdout)
        fork = run(*(words + step + ['bag_dir:=' + self.path('fork'), 'resume:=' + save]))
        self.assertEqual(fork.returncode, 0, fork.stdout)
        self.assertEqual(os.listdir(self.path('fork')), os.listdir(self.path('fresh')))
        compared = subprocess.run(COMPARE + [self.path('fresh'), self.path('fork')], stdout=subprocess.PIPE,
                                  stderr=subprocess.STDOUT, text=True)
        self.assertEqual(compared.returncode, 0, compared.stdout)
        print(compared.stdout.strip())
        # The ideal run's own bag is untouched by the forks.
        self.assertEqual(len(os.listdir(self.path('ideal'))), 1)
        # A step before the checkpoint is no fork; another run is not this one.
        early = run(*(words + ['waveform:=step_up', 'beta:=0.5', 'alpha:=100', 'resume:=' + save]))
        self.assertEqual(early.returncode, 2, early.stdout)
        self.assertIn('is no fork of ' + save, early.stdout)
        self.assertIn('first at tick 500', early.stdout)
        other = run(*(['controller:=gp_dpo', 'n_robots:=65', 'ticks:=2000', 'seed:=3', 'resume:=' + save]))
        self.assertEqual(other.returncode, 2, other.stdout)
        self.assertIn('the checkpoint has N=64 where the parameters give N=65', other.stdout)

    def test_bad_parameters_and_files_are_refused(self):
        broken = self.path('broken.ckpt')
        with open(broken, 'wb') as f:
            f.write(b'SFCKPT\r\n\x02\x00\x00\x00' + b'\xff' * 8 + b'x' * 20)
        for words, message in (
                (['checkpoint_every:=100'], 'checkpoint_every:=100 needs checkpoint:=FILE (or bag:='),
                (['checkpoint:=' + self.path('c')], 'needs checkpoint_every:=K'),
                (['save_at:=10'], 'save_at:=10 needs save:=FILE'),
                (['save:=' + self.path('s')], 'needs save_at:=T (T in [1, 100]'),
                (['save_at:=101', 'save:=' + self.path('s')], 'save_at'),
                (['checkpoint_every:=-1', 'checkpoint:=x'], 'checkpoint_every'),
                (['resume:=' + self.path('missing.ckpt')], 'resume: cannot read'),
                (['resume:=' + broken], 'is truncated'),
                (['controller:=swarm_forage_examples/levy', 'checkpoint_every:=10', 'checkpoint:=x'],
                 "controller 'swarm_forage_examples/levy' cannot be checkpointed")):
            p = run(*(['n_robots:=4', 'ticks:=100'] + words))
            self.assertEqual(p.returncode, 2, '%s: %s' % (words, p.stdout))
            self.assertIn(message, p.stdout, words)
        usage = run('--help')
        for name in ('checkpoint_every', 'checkpoint ', 'save_at', 'save ', 'resume'):
            self.assertIn(name, usage.stdout)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'checkpoint', Checkpoint)
