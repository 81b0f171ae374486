#!/usr/bin/env python3
"""Sweeps: a tiny sweep through the real `sweep` command and GNU Parallel, its resumption
after a kill while runs are in flight, and experiment files rejected before any run starts."""
import csv
import glob
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from root_only import needs_root, rosrun  # noqa: E402
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import SWEEP, TINY, sigint_default, sweep  # noqa: E402



def run_end(path):
    with rosbag.Bag(path) as bag:
        ends = [m for _, m, _ in bag.read_messages(topics=['/world/run_end'])]
        perf = [m for _, m, _ in bag.read_messages(topics=['/world/performance'])]
    return ends, perf


CLUSTER = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'slurm_cluster.sh')


def series_rows(out):
    with open(os.path.join(out, 'tables', 'series.csv')) as f:
        return f.read()


class Sweep(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.shared = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_sweeps_'))

    def setUp(self):
        self.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_sweep_'))

    def sweep(self, *args, timeout=600):
        return sweep(*args, timeout=timeout)

    def test_1_tiny_sweep_records_every_run_and_aggregates_them(self):
        out = os.path.join(self.shared, 'local')
        proc = self.sweep(write(self.tmp, 'tiny.yaml', TINY), '--out', out, '-j', '2')
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('8 runs (0 done, 8 to do)', proc.stdout)
        self.assertIn('robot-ticks/s', proc.stdout)
        bags = sorted(glob.glob(os.path.join(out, 'runs', '*.bag')))
        self.assertEqual(len(bags), 8, bags)
        finals = {}
        for path in bags:
            ends, perf = run_end(path)
            self.assertEqual(len(ends), 1, path)
            self.assertTrue(ends[0].complete, path)
            self.assertEqual(len(perf), 1500, path)
            name = os.path.basename(path)
            m = re.match(r'(.+)_[^_]+_n(\d+)_', name)  # controller_arena_nN_...: the core's record name
            controller, n = m.group(1), int(m.group(2))
            finals.setdefault((controller, n), []).append(perf[-1].cumulative)
        for table in ('scalability', 'self_organization', 'flexibility', 'series'):
            self.assertTrue(os.path.isfile(os.path.join(out, 'tables', table + '.csv')), table)
        with open(os.path.join(out, 'tables', 'series.csv')) as f:
            rows = list(csv.DictReader(f))
        last = {}
        for r in rows:
            last[(r['controller'], int(r['swarm_size']))] = r
        self.assertEqual(sorted(last), sorted(finals))
        for key, r in last.items():
            self.assertEqual(int(r['runs']), 2, key)
            self.assertAlmostEqual(float(r['P_mean']), sum(finals[key]) / 2.0, places=9, msg=str(key))
        with open(os.path.join(out, 'tables', 'scalability.csv')) as f:
            self.assertTrue(any(r['N2'] == '8' for r in csv.DictReader(f)))
        # Again: nothing to do, nothing redone.
        before = {p: os.stat(p).st_mtime_ns for p in bags}
        again = self.sweep(os.path.join(self.tmp, 'tiny.yaml'), '--out', out)
        self.assertEqual(again.returncode, 0, again.stdout)
        self.assertIn('(8 done, 0 to do)', again.stdout)
        self.assertEqual({p: os.stat(p).st_mtime_ns for p in bags}, before)

    def test_2_a_killed_sweep_resumes_without_redoing_finished_runs(self):
        spec = TINY.replace('sizes: [4, 8]', 'sizes: [256]').replace('ticks: 1500', 'ticks: 30000') \
                   .replace('runs: 2', 'runs: 3')
        path, out = write(self.tmp, 'resume.yaml', spec), os.path.join(self.tmp, 'resume')
        proc = subprocess.Popen(SWEEP + [path, '--out', out, '-j', '2'], stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True, start_new_session=True,
                                preexec_fn=sigint_default)
        runs = os.path.join(out, 'runs')
        deadline = time.time() + 300
        first_seen, first_done = {}, None
        while time.time() < deadline and proc.poll() is None:
            # A run that started after another finished, in flight for 0.3 s (of ~2 s): a kill now interrupts it.
            now = time.time()
            if first_done is None and glob.glob(os.path.join(runs, '*.bag')):
                first_done = now
            active = glob.glob(os.path.join(runs, '*.bag.*.active'))  # KEY.bag.<pid>.active
            for p in active:
                first_seen.setdefault(p, now)
            if first_done is not None and any(first_done < first_seen[p] < now - 0.3 for p in active):
                break
            time.sleep(0.02)
        else:
            proc.kill()
            self.fail('no moment with a finished run and one in flight: %s' % proc.communicate()[0])
        at_kill = sorted(os.listdir(runs))
        os.killpg(proc.pid, signal.SIGINT)  # a terminal's Ctrl-C
        output = proc.communicate(timeout=120)[0]
        self.assertNotEqual(proc.returncode, 0, output)
        self.assertIn('the same command resumes', output)
        finished = {p: (os.stat(p).st_ino, os.stat(p).st_mtime_ns)
                    for p in glob.glob(os.path.join(runs, '*.bag')) if not p.endswith('_incomplete.bag')}
        interrupted = glob.glob(os.path.join(runs, '*_incomplete.bag')) + glob.glob(os.path.join(runs, '*.active'))
        self.assertTrue(finished)
        self.assertTrue(interrupted, 'a run in flight leaves an incomplete record (at the kill: %s; after: %s; %s)'
                        % (at_kill, sorted(os.listdir(runs)), output[-1500:]))
        self.assertLess(len(finished), 6)
        again = self.sweep(path, '--out', out, '-j', '2')
        self.assertEqual(again.returncode, 0, again.stdout)
        self.assertIn('(%d done, %d to do)' % (len(finished), 6 - len(finished)), again.stdout)
        complete = [p for p in glob.glob(os.path.join(runs, '*.bag'))]
        self.assertEqual(len(complete), 6, complete)  # the incomplete records are gone, redone
        for p, ident in finished.items():
            self.assertEqual((os.stat(p).st_ino, os.stat(p).st_mtime_ns), ident, '%s was recomputed' % p)
        for p in complete:
            self.assertTrue(run_end(p)[0][0].complete, p)

    def test_3_bad_experiment_files_are_refused_before_any_run(self):
        cases = [
            (TINY + 'sizez: 4\n', 'unknown key sizez'),
            (TINY.replace('sizes: [4, 8]', 'sizes: [0, 4]'), 'sizes[0] must be a whole number >= 1'),
            (TINY.replace('sizes: [4, 8]', 'sizes: [4, 100000]'), 'n_robots must be in [1, 5181] for a 32x16 arena'),
            (TINY + 'conditions:\n  - {waveform: step_up}\n', 'waveform step_up needs beta'),
            (TINY + 'conditions:\n  - {waveform: stepup, beta: 0.2}\n', "'stepup' is not valid"),
            # Values are checked by run_experiment --conditions, the rule of a run's start-up.
            (TINY + 'conditions:\n  - {waveform: constant, beta: [0.2, 1.5]}\n',
             'conditions[0]: beta must be in [-1, 1] (negative boosts; got 1.5)'),
            (TINY + 'conditions:\n  - {waveform: step_up, beta: 0.2, alpha: 1e9}\n', 'is not within the run'),
            (TINY.replace('controllers: [crw, dpo]', 'controllers: [crw, ant]'), 'controllers must be a list'),
            (TINY + 'params: {crw/wander_forse: 3}\n', 'wander_forse is not a crw constant'),
            ('name: x\narena: [unclosed\n', 'not valid YAML'),
            (TINY + 'model: bogus\n', "model 'bogus' is unknown; valid: fordyca_2019, swarm_forage"),
            (TINY + 'quirks: [heading_estimat]\n', "quirks: 'heading_estimat' is not a quirk; valid: "
             'transport_wander,'),
            (TINY + 'params: {model: fordyca_2019}\n', 'params.model is set by the sweep itself'),
        ]
        for k, (text, message) in enumerate(cases):
            out = os.path.join(self.tmp, 'bad%d' % k)
            proc = self.sweep(write(self.tmp, 'bad%d.yaml' % k, text), '--out', out)
            self.assertEqual(proc.returncode, 2, proc.stdout)
            self.assertIn(message, proc.stdout)
            self.assertFalse(glob.glob(os.path.join(out, 'runs', '*')), 'case %d ran something' % k)
        locked = os.path.join(self.tmp, 'locked')
        os.makedirs(locked)
        os.chmod(locked, 0o500)
        proc = self.sweep(write(self.tmp, 'ok.yaml', TINY), '--out', os.path.join(locked, 'out'))
        if os.geteuid() != 0:  # root writes anywhere; then a path under a file stands in
            self.assertEqual(proc.returncode, 2, proc.stdout)
            self.assertIn('is not writable', proc.stdout)
        blocker = write(self.tmp, 'a_file', '')
        proc = self.sweep(os.path.join(self.tmp, 'ok.yaml'), '--out', os.path.join(blocker, 'out'))
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('is not writable', proc.stdout)


    @needs_root('the one-node SLURM of slurm_cluster.sh', sudo=True)
    def test_4_slurm_array_gives_the_local_results(self):
        """A real one-node SLURM (munged, slurmctld, slurmd of its own), the tiny sweep with --slurm."""
        local = os.path.join(self.shared, 'local')
        if not os.path.isdir(local):
            self.assertEqual(self.sweep(write(self.tmp, 'tiny.yaml', TINY), '--out', local).returncode, 0)
        os.chmod(self.tmp, 0o755)  # munged runs as user munge: it must reach its folder
        cluster = os.path.join(self.tmp, 'cluster')
        env = dict(os.environ, SLURM_CONF=os.path.join(cluster, 'slurm.conf'), SLURM_TEST_PORT=str(16900 + os.getpid() % 50))
        sudo = [] if os.geteuid() == 0 else ['sudo', '-n', '-E']
        start = subprocess.run(sudo + [CLUSTER, 'start', cluster], env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=120)
        try:
            self.assertEqual(start.returncode, 0, 'a one-node SLURM needs root (or sudo) and slurm-wlm, munge: '
                             + start.stdout)
            out = os.path.join(self.tmp, 'slurm')
            proc = subprocess.run(SWEEP + [write(self.tmp, 'tiny.yaml', TINY), '--out', out, '--slurm', '--chunk', '3'],
                                  env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            self.assertIn('submitting', proc.stdout)
            self.assertEqual(len(glob.glob(os.path.join(out, 'slurm', '*.out'))), 3, 'one log per array task')
            names = lambda d: sorted(os.path.basename(p) for p in glob.glob(os.path.join(d, 'runs', '*.bag')))
            self.assertEqual(names(out), names(local))
            self.assertEqual(series_rows(out), series_rows(local))
            for table in ('scalability', 'self_organization'):
                with open(os.path.join(out, 'tables', table + '.csv')) as a, \
                        open(os.path.join(local, 'tables', table + '.csv')) as b:
                    self.assertEqual(a.read(), b.read(), table)
        finally:
            subprocess.run(sudo + [CLUSTER, 'stop', cluster], env=env, timeout=60)

    def test_5_graph_mode_gives_the_headless_results(self):
        """--graph: every run through the node graph with a private master gives the headless records, with
        the experiment's params (a controller constant and a launch argument) applied in both; a param the
        graph cannot be given is refused before any run."""
        spec = TINY.replace('sizes: [4, 8]', 'sizes: [4]').replace('ticks: 1500', 'ticks: 600')
        spec += 'params: {dpo/pheromone_decay: 0.001, serialize_block_ops: true}\n'
        path = write(self.tmp, 'graph.yaml', spec)
        graph, headless = os.path.join(self.tmp, 'graph'), os.path.join(self.tmp, 'headless')
        for out, extra in ((graph, ['--graph']), (headless, [])):
            proc = self.sweep(path, '--out', out, '-j', '2', *extra)
            self.assertEqual(proc.returncode, 0, proc.stdout)
        # series.csv names each group's identity, which holds the constants: equal rows, equal constants.
        self.assertEqual(series_rows(graph), series_rows(headless))
        self.assertEqual(len(glob.glob(os.path.join(graph, 'runs', '*.bag'))), 4)
        with rosbag.Bag(glob.glob(os.path.join(graph, 'runs', 'dpo_*.bag'))[0]) as bag:
            info = next(m for _, m, _ in bag.read_messages(topics=['/world/run_info']))
        self.assertIn('dpo/pheromone_decay=0.001', info.controller_constants)
        self.assertIn('serialize_block_ops=1', info.world_constants)
        los = write(self.tmp, 'los.yaml', spec.replace('serialize_block_ops: true', 'los_radius: 3'))
        proc = self.sweep(los, '--out', os.path.join(self.tmp, 'los'), '--graph')
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('params.los_radius cannot reach the node graph', proc.stdout)

    def test_6_the_model_of_an_experiment_reaches_every_run(self):
        """model: (and quirks:, or sweep --model/--quirks): every run carries its quirks in its identity
        (world/run_info's constants) and its record name says what differs from the default model
        (fordyca_2019): nothing for it, `_swarm_forage` for the corrected model, the quirks added on top;
        unknown names are refused with the valid ones; the default model, named or not, adds no word."""
        from swarm_forage.experiment import file as experiment_file
        from swarm_forage.experiment.plan import expand
        spec = TINY.replace('sizes: [4, 8]', 'sizes: [4]').replace('ticks: 1500', 'ticks: 300') \
                   .replace('runs: 2', 'runs: 1').replace('controllers: [crw, dpo]', 'controllers: [dpo]')
        world_q = 'quirks=rim_ground_sensors,block_penalties,light_occlusion'
        controller_q = 'quirks=transport_wander,absolute_recovery_angle,first_collision_at_zero,' \
                       'compressed_arrival,heading_estimate'
        # (file text, sweep words, word in the record name, world quirks, controller quirks)
        cases = [(spec + 'model: fordyca_2019\n', [], None, world_q, controller_q),
                 (spec, ['--quirks', 'dynamics2d_contacts'], '_dynamics2d_contacts', world_q + ',dynamics2d_contacts',
                  controller_q),
                 (spec + 'model: swarm_forage\n', [], '_swarm_forage', None, None)]
        for k, (text, extra, word, world_quirks, controller_quirks) in enumerate(cases):
            out = os.path.join(self.tmp, 'model%d' % k)
            proc = self.sweep(write(self.tmp, 'model%d.yaml' % k, text), '--out', out, *extra)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            bags = sorted(glob.glob(os.path.join(out, 'runs', '*.bag')))
            self.assertEqual(len(bags), 1, bags)
            for path in bags:
                name = os.path.basename(path)
                self.assertNotIn('fordyca_2019', name)
                if word:
                    self.assertIn(word, name)
                else:
                    self.assertNotIn('swarm_forage', name)
                with rosbag.Bag(path) as bag:
                    info = next(m for _, m, _ in bag.read_messages(topics=['/world/run_info']))
                for constants, quirks in ((info.world_constants, world_quirks),
                                          (info.controller_constants, controller_quirks)):
                    if quirks:
                        self.assertIn(quirks, constants, path)
                    else:
                        self.assertNotIn('quirks=', constants, path)
        for extra, message in ((['--model', 'bogus'], "--model 'bogus' is unknown; valid: fordyca_2019, swarm_forage"),
                               (['--quirks', 'heading_estimate,nope'], "--quirks: 'nope' is not a quirk; valid: ")):
            proc = self.sweep(write(self.tmp, 'ok.yaml', spec), '--out', os.path.join(self.tmp, 'bad'), *extra)
            self.assertEqual(proc.returncode, 2, proc.stdout)
            self.assertIn(message, proc.stdout)
        # The default model, named or not, adds no word.
        plain = expand(experiment_file.load(write(self.tmp, 'plain.yaml', TINY)))
        named = expand(experiment_file.load(write(self.tmp, 'named.yaml', TINY + 'model: fordyca_2019\n'
                                                        'quirks: []\n')))
        self.assertEqual([r['key'] for r in named], [r['key'] for r in plain])
        for r in plain:
            self.assertFalse([w for w in r['args'] if w.startswith(('model:=', 'quirks:='))], r['args'])
        one = expand(experiment_file.load(os.path.join(self.tmp, 'plain.yaml'), {'quirks': 'dynamics2d_contacts'}))
        self.assertIn('quirks:=dynamics2d_contacts', one[0]['args'])
        self.assertNotEqual(one[0]['key'], plain[0]['key'])

    def test_7_compression_is_chosen_and_changes_no_result(self):
        """--compression lz4: every record's chunks are lz4, the plan says so, and the tables equal the bz2
        sweep's; a compression rosbag does not write is refused before any run."""
        local = os.path.join(self.shared, 'local')
        if not os.path.isdir(local):
            self.assertEqual(self.sweep(write(self.tmp, 'tiny.yaml', TINY), '--out', local).returncode, 0)
        out = os.path.join(self.tmp, 'lz4')
        proc = self.sweep(write(self.tmp, 'tiny.yaml', TINY), '--out', out, '--compression', 'lz4')
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('(lz4, one snapshot', proc.stdout)
        bags = glob.glob(os.path.join(out, 'runs', '*.bag'))
        self.assertEqual(len(bags), 8, bags)
        for path in bags:
            with rosbag.Bag(path) as bag:
                self.assertEqual({h.compression for h in bag._chunk_headers.values()}, {'lz4'}, path)
        with rosbag.Bag(glob.glob(os.path.join(local, 'runs', '*.bag'))[0]) as bag:
            self.assertEqual({h.compression for h in bag._chunk_headers.values()}, {'bz2'})
        self.assertEqual(series_rows(out), series_rows(local))
        proc = self.sweep(os.path.join(self.tmp, 'tiny.yaml'), '--out', os.path.join(self.tmp, 'bad'),
                          '--compression', 'zip')
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn("--compression: invalid choice: 'zip' (choose from 'bz2', 'lz4', 'none')", proc.stdout)
        self.assertFalse(os.path.exists(os.path.join(self.tmp, 'bad')))


if __name__ == '__main__':
    rosrun('swarm_forage', 'sweep', Sweep)
