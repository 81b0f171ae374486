#!/usr/bin/env python3
"""A bag is never replaced or shared: parameters an earlier launch left on the master never make a run
record (or overwrite) a bag; an existing bag:= is refused unless overwrite:=true; runs writing into one
folder side by side each get their own record; a record that cannot take its name ends the run non-zero."""
import glob
import hashlib
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rostest

SMALL = ['n_robots:=4', 'ticks:=300']
GRAPH = SMALL + ['metrics:=false', 'wait_for_subscribers:=0']


def digest(path):
    with open(path, 'rb') as f:
        return hashlib.sha1(f.read()).hexdigest()


def forage(*args):
    return subprocess.run(['rosrun', 'swarm_forage', 'forage'] + GRAPH + list(args), stdout=subprocess.PIPE,
                          stderr=subprocess.STDOUT, text=True, timeout=300)


def headless(*args):
    return subprocess.Popen(['rosrun', 'swarm_forage', 'run_experiment'] + list(args), stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)


def run_end(path):
    with rosbag.Bag(path) as bag:
        ends = [m for _, m, _ in bag.read_messages(topics=['/world/run_end'])]
        seeds = [m.seed for _, m, _ in bag.read_messages(topics=['/world/run_info'])]
    return ends[-1], seeds


def wait_for(pattern, proc, timeout=600):
    """The first file matching `pattern` while `proc` runs (event-based: no wall-clock slack assumed)."""
    deadline = time.time() + timeout
    while time.time() < deadline and proc.poll() is None:
        found = glob.glob(pattern)
        if found:
            return found[0]
        time.sleep(0.01)
    return None


class Recording(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_recording_')

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def test_leftover_parameters_record_nothing(self):
        first = os.path.join(self.tmp, 'first.bag')
        r = forage('record:=true', 'bag:=' + first, 'seed:=1')
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        before = digest(first)
        # The same master, no record: world_node must not find first.bag's ~bag still set.
        r = forage('seed:=2', 'results:=' + self.tmp)
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertEqual(digest(first), before, 'a run without record:=true rewrote the earlier bag')
        self.assertEqual(sorted(os.listdir(self.tmp)), ['first.bag'])
        self.assertEqual(run_end(first)[1], [1])
        # A run named by its identity (~bag_dir), then one with bag:= again: never "both set".
        lib = os.path.join(self.tmp, 'lib')
        r = forage('record:=true', 'results:=' + lib, 'seed:=3')
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        second = os.path.join(self.tmp, 'second.bag')
        r = forage('record:=true', 'bag:=' + second, 'seed:=4')
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertEqual(run_end(second)[1], [4])
        self.assertEqual(len(os.listdir(lib)), 1)

    def test_existing_bag_refused_unless_overwrite(self):
        bag = os.path.join(self.tmp, 'run.bag')
        p = headless('bag:=' + bag, 'seed:=1', *SMALL)
        self.assertEqual(p.wait(), 0, p.stdout.read())
        before = digest(bag)
        p = headless('bag:=' + bag, 'seed:=2', *SMALL)
        out = p.communicate()[0]
        self.assertEqual(p.returncode, 2, out)
        self.assertIn("~bag '%s' exists: give a new path, or ~overwrite true to replace it" % bag, out)
        r = forage('record:=true', 'bag:=' + bag, 'seed:=2')
        self.assertNotEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertIn("~bag '%s' exists" % bag, r.stdout)
        self.assertEqual(digest(bag), before)
        p = headless('bag:=' + bag, 'seed:=2', 'overwrite:=true', *SMALL)
        self.assertEqual(p.wait(), 0, p.stdout.read())
        self.assertEqual(run_end(bag)[1], [2])
        r = forage('record:=true', 'bag:=' + bag, 'seed:=3', 'overwrite:=true')
        self.assertEqual(r.returncode, 0, r.stdout[-3000:])
        self.assertEqual(run_end(bag)[1], [3])
        self.assertEqual(os.listdir(self.tmp), ['run.bag'])

    def test_concurrent_runs_into_one_folder(self):
        folder = os.path.join(self.tmp, 'bdc')
        common = ['bag_dir:=' + folder, 'controller:=crw', 'n_robots:=16', 'seed:=1', 'ticks:=2000']
        conditions = [[], ['waveform:=constant', 'beta:=0.3'], []]  # two differ in waveform only, two are equal
        procs = [headless(*(common + c)) for c in conditions]
        for p in procs:
            self.assertEqual(p.wait(), 0, p.stdout.read())
        bags = sorted(os.listdir(folder))
        self.assertEqual(len(bags), 3, bags)
        self.assertEqual(len([b for b in bags if '_null_' in b]), 2, bags)
        self.assertTrue(any(b.endswith('_2.bag') for b in bags), bags)
        for b in bags:
            end, seeds = run_end(os.path.join(folder, b))
            self.assertTrue(end.complete, b)
            self.assertEqual(seeds, [1])

    def test_record_that_cannot_take_its_name(self):
        for name, start in (('headless', lambda bag: headless('bag:=' + bag, 'n_robots:=64', 'ticks:=100000')),
                            ('graph', lambda bag: subprocess.Popen(
                                ['rosrun', 'swarm_forage', 'forage', 'record:=true', 'bag:=' + bag, 'n_robots:=64',
                                 'ticks:=3000', 'metrics:=false', 'wait_for_subscribers:=0'],
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True))):
            bag = os.path.join(self.tmp, name + '.bag')
            proc = start(bag)
            active = wait_for(bag + '.*.active', proc)
            self.assertIsNotNone(active, '%s: no temporary record appeared' % name)
            with open(bag, 'w') as f:  # another writer takes the name while the run is on
                f.write('not this run')
            out = proc.communicate(timeout=300)[0]
            self.assertEqual(proc.returncode, 1, out[-3000:])
            self.assertIn('cannot name the record %s (%s exists); it is kept as %s' % (bag, bag, active), out)
            self.assertTrue(run_end(active)[0].complete)  # the run itself is whole, and kept
            with open(bag) as f:
                self.assertEqual(f.read(), 'not this run')
            os.remove(bag)
            # A run library tells the record kept under its temporary name from a finished one.
            tables = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', self.tmp, 'out:=' + self.tmp + '/t'],
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
            self.assertIn(active + ': never closed', tables.stdout)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'recording', Recording, sys.argv)
