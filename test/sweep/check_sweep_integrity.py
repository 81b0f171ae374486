#!/usr/bin/env python3
"""A sweep never loses, mixes or silently reuses a record: one sweep per folder, a record
counts only if whole and of the planned run, keys from the input files' content, --dry-run and --help
change nothing, and bad plans are refused. Each case sets up the failure first."""
import contextlib
import glob
import os
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import unittest

import rosbag
import rostest
sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import sigint_default  # noqa: E402

PACKAGE = os.path.dirname(os.path.dirname(os.path.dirname(os.path.realpath(__file__))))
from swarm_forage.experiment import file as experiment_file  # noqa: E402
from swarm_forage.experiment.plan import expand  # noqa: E402
from swarm_forage.sweep import estimate, records  # noqa: E402

SWEEP = ['rosrun', 'swarm_forage', 'sweep']
TINY = """name: tiny
arena: %s
controllers: [crw]
sizes: [2, 4]
runs: 2
ticks: 300
sample_interval: 100
"""


def listing(folder):
    """Every path under `folder` with its size and mtime (what `--dry-run` must leave as it is)."""
    out = {}
    for root, dirs, files in os.walk(folder):
        for name in dirs + files:
            path = os.path.join(root, name)
            st = os.lstat(path)
            out[os.path.relpath(path, folder)] = (st.st_size, st.st_mtime_ns)
    return out


def dead_pid():
    proc = subprocess.Popen(['true'])
    proc.wait()
    return proc.pid


class SweepIntegrity(unittest.TestCase):
    def setUp(self):
        self.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_sweep_integrity_'))
        self.env = dict(os.environ, TMPDIR=os.path.join(self.tmp, 'tmpdir'))  # the calibration's folder
        os.makedirs(self.env['TMPDIR'])
        self.spec = write(self.tmp, 'tiny.yaml', TINY % '32x16')

    def tearDown(self):
        self.assertEqual(os.listdir(self.env['TMPDIR']), [], 'the sweep left files in TMPDIR')
        shutil.rmtree(self.tmp, ignore_errors=True)

    def sweep(self, *args):
        return subprocess.run(SWEEP + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              env=self.env, timeout=600)

    def start(self, *args):
        return subprocess.Popen(SWEEP + list(args), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                env=self.env, start_new_session=True, preexec_fn=sigint_default)

    @contextlib.contextmanager
    def started(self, *args):
        """A sweep started in a session of its own, killed with its runs if the test leaves it running."""
        proc = self.start(*args)
        try:
            yield proc
        finally:
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()

    @staticmethod
    @contextlib.contextmanager
    def paused(proc):
        """The sweep `proc` and its runs stopped (SIGSTOP) meanwhile: it holds its lock however slow the rest."""
        os.killpg(proc.pid, signal.SIGSTOP)
        try:
            yield
        finally:
            os.killpg(proc.pid, signal.SIGCONT)

    def wait_for(self, what, proc):
        while not what():
            if proc.poll() is not None:
                self.fail('the sweep ended first: %s' % proc.communicate()[0])
            time.sleep(0.02)

    def plan(self, spec, **overrides):
        return {r['key']: r for r in expand(experiment_file.load(spec, overrides))}

    def assert_all_verify(self, out, spec, **overrides):
        version = records.model_version()[0]
        plan = self.plan(spec, **overrides)
        for key, run in plan.items():
            path = os.path.join(out, 'runs', key + '.bag')
            self.assertEqual(records.verify(path, run, version), '', path)
            with rosbag.Bag(path) as bag:  # every message readable
                self.assertEqual(sum(1 for m in bag.read_messages(topics=['/world/performance'])), run['ticks'])
        return plan

    def test_1_a_second_sweep_on_a_folder_refuses_naming_the_holder(self):
        out = os.path.join(self.tmp, 'out')
        with self.started(self.spec, '--out', out, '-j', '2') as first:
            self.wait_for(lambda: records.read_holder(out).get('pid') == str(first.pid), first)
            with self.paused(first):  # holds the lock however slow the second one starts
                second = self.sweep(self.spec, '--out', out, '-j', '2')
            self.assertEqual(second.returncode, 3, second.stdout)
            self.assertIn('is in use by sweep pid %d on %s since ' % (first.pid, socket.gethostname()), second.stdout)
            output = first.communicate(timeout=600)[0]
        self.assertEqual(first.returncode, 0, output)
        self.assertIn('complete: 4 runs', output)
        self.assertIn('ceiling loop ran at', output)  # how sure the estimate is
        self.assert_all_verify(out, self.spec)
        self.assertEqual(records.read_holder(out), {}, 'the lock is released at the end')

    def test_2_a_stale_lock_of_a_dead_sweep_is_taken_over(self):
        out = os.path.join(self.tmp, 'out')
        os.makedirs(out)
        pid = dead_pid()
        write(out, 'sweep.lock', 'pid: %d\nhost: %s\nstart: 2024-01-01 00:00:00\ncommand: sweep x\n'
              % (pid, socket.gethostname()))
        proc = self.sweep(self.spec, '--out', out)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('taking over %s from sweep pid %d on %s since 2024-01-01' % (
            os.path.join(out, 'sweep.lock'), pid, socket.gethostname()), proc.stdout)
        self.assert_all_verify(out, self.spec)

    def test_3_a_broken_record_is_rejected_and_redone_and_an_unfixed_problem_fails(self):
        out = os.path.join(self.tmp, 'out')
        self.assertEqual(self.sweep(self.spec, '--out', out).returncode, 0)
        plan = self.plan(self.spec)
        key = sorted(plan)[0]
        bag = os.path.join(out, 'runs', key + '.bag')
        os.truncate(bag, os.path.getsize(bag) // 2)
        proc = self.sweep(self.spec, '--out', out)
        self.assertEqual(proc.returncode, 0, proc.stdout)  # rejected, redone: nothing left to fix
        self.assertIn('1 records moved to %s and redone: %s: cannot be read' % (
            os.path.join(out, 'runs', 'rejected'), key), proc.stdout)
        self.assertIn('(3 done, 1 to do)', proc.stdout)
        with open(os.path.join(out, 'runs', 'rejected', key + '.reason')) as f:
            self.assertIn('cannot be read', f.read())
        self.assertTrue(os.path.isfile(os.path.join(out, 'runs', 'rejected', key + '.bag')))
        self.assert_all_verify(out, self.spec)
        # A chunk broken in the middle: index, run_info and run_end intact, so only run_tables finds it.
        long_spec = write(self.tmp, 'long.yaml', TINY.replace('sizes: [2, 4]', 'sizes: [4]')
                          .replace('ticks: 300', 'ticks: 20000').replace('runs: 2', 'runs: 1') % '32x16')
        long_out = os.path.join(self.tmp, 'long')
        self.assertEqual(self.sweep(long_spec, '--out', long_out).returncode, 0)
        (key,) = self.plan(long_spec)
        bag = os.path.join(long_out, 'runs', key + '.bag')
        with rosbag.Bag(bag) as b:
            chunks = [c.pos for c in b._chunks]
        self.assertGreaterEqual(len(chunks), 3, 'the record needs a chunk in the middle')
        with open(bag, 'r+b') as f:
            f.seek(chunks[len(chunks) // 2] + 200)
            f.write(b'\0' * 64)
        proc = self.sweep(long_spec, '--out', long_out)
        self.assertEqual(proc.returncode, 1, proc.stdout)
        self.assertIn('problem: run_tables: %s' % os.path.join(long_out, 'plan', key + '.bag'), proc.stdout)
        self.assertIn('finished with', proc.stdout)
        self.assertTrue(os.path.isfile(os.path.join(long_out, 'runs', 'rejected', key + '.reason')))
        again = self.sweep(long_spec, '--out', long_out)
        self.assertEqual(again.returncode, 0, again.stdout)
        self.assertIn('(0 done, 1 to do)', again.stdout)

    def test_4_an_edited_arena_gives_new_keys_and_old_records_stay_out_of_the_tables(self):
        with open(os.path.join(PACKAGE, 'config', 'arenas', '32x16.yaml')) as f:
            arena = f.read()
        write(self.tmp, 'arena.yaml', arena)
        spec = write(self.tmp, 'own_arena.yaml', TINY % './arena.yaml')
        out = os.path.join(self.tmp, 'out')
        self.assertEqual(self.sweep(spec, '--out', out).returncode, 0)
        old = self.plan(spec)
        write(self.tmp, 'arena.yaml', arena.replace('width: 32.0', 'width: 30.0'))
        new = self.plan(spec)
        self.assertFalse(set(old) & set(new), 'an edited arena file must change every key')
        proc = self.sweep(spec, '--out', out)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('(0 done, 4 to do)', proc.stdout)
        self.assertIn('4 records in %s are not in this plan' % os.path.join(out, 'runs'), proc.stdout)
        self.assertEqual(sorted(os.listdir(os.path.join(out, 'plan'))), sorted(k + '.bag' for k in new))
        with open(os.path.join(out, 'tables', 'series.csv')) as f:
            runs = {line.split(',')[6] for line in f.read().splitlines()[1:]}
        self.assertEqual(runs, {'2'}, 'each group holds its 2 seeds, not the old arena\'s too')
        self.assert_all_verify(out, spec)

    def rewrite(self, path, change):
        """The bag at `path` again with `change(topic, msg)` applied to every message."""
        tmp = path + '.rewritten'
        with rosbag.Bag(path) as src, rosbag.Bag(tmp, 'w') as dst:
            for topic, msg, t in src.read_messages():
                change(topic, msg)
                dst.write(topic, msg, t)
        os.replace(tmp, path)

    def test_5_a_record_of_another_seed_label_or_model_version_is_rejected(self):
        out = os.path.join(self.tmp, 'out')
        self.assertEqual(self.sweep(self.spec, '--out', out).returncode, 0)
        plan = self.plan(self.spec)
        by = {(r['n'], r['seed']): k for k, r in plan.items()}
        runs = os.path.join(out, 'runs')
        path = lambda n, s: os.path.join(runs, by[(n, s)] + '.bag')  # noqa: E731
        shutil.copyfile(path(2, 1), path(2, 2))  # seed 1's record under seed 2's key
        self.rewrite(path(4, 1), lambda t, m: setattr(m, 'label', 'another') if t == '/world/provenance' else None)
        self.rewrite(path(4, 2), lambda t, m: setattr(m, 'model_version', m.model_version + 1)
                     if t == '/world/provenance' else None)
        proc = self.sweep(self.spec, '--out', out)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('3 records moved', proc.stdout)
        reasons = {}
        for name in glob.glob(os.path.join(runs, 'rejected', '*.reason')):
            with open(name) as f:
                reasons[os.path.basename(name)[:-7]] = f.read()
        self.assertEqual(sorted(reasons), sorted([by[(2, 2)], by[(4, 1)], by[(4, 2)]]))
        self.assertIn('world/run_info seed is 1 (the plan wants 2)', reasons[by[(2, 2)]])
        self.assertIn("world/provenance label is 'another'", reasons[by[(4, 1)]])
        self.assertIn('this code is model version', reasons[by[(4, 2)]])
        self.assert_all_verify(out, self.spec)

    def test_5b_run_tables_never_groups_records_of_different_model_versions(self):
        out = os.path.join(self.tmp, 'out')
        self.assertEqual(self.sweep(self.spec, '--out', out).returncode, 0)
        key = sorted(self.plan(self.spec))[0]
        self.rewrite(os.path.join(out, 'runs', key + '.bag'),
                     lambda t, m: setattr(m, 'model_version', m.model_version + 1) if t == '/world/provenance' else None)
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_tables', os.path.join(out, 'runs'),
                               'out:=' + os.path.join(self.tmp, 'tables')],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600)
        self.assertIn('records of different model versions are never grouped', proc.stdout)
        line = next(x for x in proc.stdout.splitlines() if 'never grouped' in x)
        self.assertIn(key + '.bag', line)

    def test_5c_inputs_edited_during_a_sweep_stop_it_and_no_record_of_them_is_kept(self):
        with open(os.path.join(PACKAGE, 'config', 'arenas', '32x16.yaml')) as f:
            arena = f.read()
        write(self.tmp, 'arena.yaml', arena)
        spec = write(self.tmp, 'edited.yaml', (TINY % './arena.yaml').replace('runs: 2', 'runs: 3'))
        out = os.path.join(self.tmp, 'out')
        with self.started(spec, '--out', out, '-j', '1') as running:
            self.wait_for(lambda: glob.glob(os.path.join(out, 'runs', '*.bag')), running)
            write(self.tmp, 'arena.yaml', arena.replace('width: 32.0', 'width: 30.0'))
            said = running.communicate(timeout=600)[0]
        self.assertEqual(running.returncode, 1, said)
        self.assertIn('the inputs changed during the sweep', said)
        self.assertIn('refused to start, their identity no longer the planned one', said)
        write(self.tmp, 'arena.yaml', arena)  # back to the plan's inputs: what was recorded is of the plan
        again = self.sweep(spec, '--out', out)
        self.assertEqual(again.returncode, 0, again.stdout)
        self.assertNotIn('rejected', again.stdout)
        self.assert_all_verify(out, spec)

    def test_5d_the_core_names_a_run_before_it_runs_and_a_run_refuses_another_identity(self):
        words = ['controller:=crw', 'arena:=32x16', 'n_robots:=4', 'seed:=2', 'ticks:=300']
        asked = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--identity'],
                               input='\t'.join(words) + '\n' + '\t'.join(words[:2] + ['n_robots:=-1']) + '\n',
                               stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=120)
        self.assertEqual(asked.returncode, 0, asked.stdout)
        ok, bad = asked.stdout.splitlines()
        verdict, identity, name = ok.split('\t')
        self.assertEqual((verdict, name), ('ok', 'crw_32x16_n4_null_seed2_%s.bag' % identity))
        self.assertTrue(bad.startswith('error\t~n_robots must be in [1, '), bad)
        bag_dir = os.path.join(self.tmp, 'named')
        os.makedirs(bag_dir)
        run = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment'] + words + ['bag_dir:=' + bag_dir],
                             stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
        self.assertEqual(run.returncode, 0, run.stdout)
        self.assertEqual(os.listdir(bag_dir), [name])  # the run's record has the name it was given before
        refused = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment'] + words +
                                 ['expect_identity:=00000000', 'bag:=' + os.path.join(self.tmp, 'refused.bag')],
                                 stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
        self.assertEqual(refused.returncode, 3, refused.stdout)
        self.assertIn("the run's identity is %s where expect_identity:=00000000 was planned" % identity,
                      refused.stdout)
        self.assertFalse(glob.glob(os.path.join(self.tmp, 'refused*')), 'a refused run records nothing')

    def test_6_dry_run_beside_a_running_sweep_writes_nothing(self):
        fresh = os.path.join(self.tmp, 'fresh')
        proc = self.sweep(self.spec, '--out', fresh, '--dry-run')
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('(0 done, 4 to do)', proc.stdout)
        self.assertFalse(os.path.exists(fresh), 'a dry run made its output folder')
        out = os.path.join(self.tmp, 'out')
        with self.started(self.spec, '--out', out) as running:
            self.wait_for(lambda: os.path.exists(os.path.join(out, 'todo.txt')), running)
            with self.paused(running):
                key = sorted(self.plan(self.spec))[0]
                # What the old dry run deleted: partial records of another writer.
                write(os.path.join(out, 'runs'), key + '.bag.active', 'in flight')
                write(os.path.join(out, 'runs'), '%s.bag.%d.active' % (key, running.pid), 'in flight')
                before = listing(out)
                dry = self.sweep(self.spec, '--out', out, '--dry-run')
                after = listing(out)
            output = running.communicate(timeout=600)[0]
        self.assertEqual(dry.returncode, 0, dry.stdout)
        self.assertIn('is in use by sweep pid %d' % running.pid, dry.stdout)
        self.assertEqual(after, before, 'the dry run changed the folder')
        self.assertEqual(running.returncode, 0, output)

    def test_7_help_of_every_python_command_prints_usage_and_runs_nothing(self):
        commands = ['scripts/sweep', 'scripts/paper', 'scripts/health', 'scripts/make_reference_bags', 'scripts/forage',
                    'scripts/summarize_run.py', 'scripts/plot_sweep.py', 'scripts/plot_metrics.py',
                    'scripts/paper_report.py', 'bench/bench_all.py', 'bench/bench_graph.py']
        cwd = os.path.join(self.tmp, 'cwd')
        os.makedirs(cwd)
        results = os.path.join(PACKAGE, 'results')
        before = listing(results) if os.path.isdir(results) else {}
        for command in commands:
            extra = {'scripts/paper': ['--quick'], 'scripts/forage': ['n_robots:=1']}.get(command, [])
            proc = subprocess.run([sys.executable, os.path.join(PACKAGE, command)] + extra + ['--help'], cwd=cwd,
                                  env=self.env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                                  timeout=120)
            self.assertEqual(proc.returncode, 0, '%s --help: %s' % (command, proc.stdout))
            self.assertIn('usage', proc.stdout.lower(), command)
            self.assertIn('example', proc.stdout.lower(), command)
            self.assertEqual(os.listdir(cwd), [], '%s --help wrote files' % command)
            self.assertEqual(listing(results) if os.path.isdir(results) else {}, before, '%s --help wrote' % command)
        # A bad count of busy processes is refused before anything runs, naming the range.
        proc = subprocess.run([sys.executable, os.path.join(PACKAGE, 'bench', 'bench_all.py'), '--noise', '99'],
                              cwd=cwd, env=self.env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              timeout=120)
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('--noise must be 0 to 64 busy processes (got 99)', proc.stdout)
        self.assertEqual(os.listdir(cwd), [], 'bench_all --noise 99 wrote files')

    def test_8_an_output_folder_with_a_space_works(self):
        folder = os.path.join(self.tmp, 'my experiments')
        os.makedirs(folder)
        with open(os.path.join(PACKAGE, 'config', 'arenas', '32x16.yaml')) as f:
            write(folder, 'arena one.yaml', f.read())
        spec = write(folder, 'tiny.yaml', TINY % "'./arena one.yaml'")  # a path with a space too
        out = os.path.join(folder, 'sweep out')
        proc = self.sweep(spec, '--out', out, '-j', '2')
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('complete: 4 runs', proc.stdout)
        self.assert_all_verify(out, spec)

    def test_9_contradictory_plans_are_refused(self):
        out = os.path.join(self.tmp, 'out')
        cases = [(['--sizes', '8,16', '--max-size', '4'], '--max-size 4 is below every swarm size (8, 16)'),
                 (['--sizes', '4,4'], 'sizes lists 4 more than once'),
                 (['--controllers', 'crw,crw'], 'controllers lists crw more than once')]
        for args, message in cases:
            proc = self.sweep(self.spec, '--out', out, *args)
            self.assertEqual(proc.returncode, 2, proc.stdout)
            self.assertIn(message, proc.stdout)
        twice = write(self.tmp, 'twice.yaml',
                      TINY % '32x16' + 'conditions:\n  - {waveform: step_down, beta: [0.2, 0.2]}\n')
        proc = self.sweep(twice, '--out', out)
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('conditions list step_down0.2 twice', proc.stdout)
        self.assertFalse(os.path.exists(out), 'a refused plan made its output folder')

    def test_10_a_kill_during_calibration_leaves_nothing(self):
        for sig in (signal.SIGTERM, signal.SIGINT):
            out = os.path.join(self.tmp, 'out%d' % sig)
            proc = self.start(self.spec, '--out', out)
            tmpdir = self.env['TMPDIR']
            self.wait_for(lambda: any(n.startswith('swarm_forage_calibration_') for n in os.listdir(tmpdir)), proc)
            proc.send_signal(sig)  # the sweep alone, as `kill PID` does
            output = proc.communicate(timeout=120)[0]
            self.assertNotEqual(proc.returncode, 0, output)
            self.assertIn('the same command resumes', output)
            self.assertEqual(os.listdir(tmpdir), [], 'signal %d left the calibration folder' % sig)
            self.assertEqual(records.read_holder(out), {}, 'the lock is released')

    def test_11_progress_weights_runs_by_calibrated_cost(self):
        out = os.path.join(self.tmp, 'out')
        os.makedirs(os.path.join(out, 'runs'))
        # Many robot-ticks but cheap (one start-up) against few but expensive: robot-ticks would say 99 %.
        todo = [{'key': 'big', 'controller': 'crw', 'n': 1000, 'ticks': 990}, {'key': 'slow', 'controller': 'gp_dpo',
                                                                               'n': 1, 'ticks': 10}]
        costs = {('crw', ''): (0.0, 1e-9), ('gp_dpo', ''): (1.0, 0.0)}  # by (controller, model)
        progress = estimate.Progress(out, todo, lambda r: estimate.run_cost(r, costs, 0.5))
        write(os.path.join(out, 'runs'), 'big.bag', '')
        progress.update()
        cost_big, cost_slow = 0.5 + 990 * 1000 * 1e-9, 0.5 + 10 * 1.0
        self.assertAlmostEqual(progress.fraction, cost_big / (cost_big + cost_slow))
        self.assertLess(progress.fraction, 0.1)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage', 'sweep_integrity', SweepIntegrity)
