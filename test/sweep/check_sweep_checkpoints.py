#!/usr/bin/env python3
"""The sweep's side of checkpoints:
(1) forks: a sweep of ideal, step_up and step_down runs runs each ideal run once with `save_at:=` at alpha
and starts the step_up runs from its checkpoint (`resume:=`); the plan counts the forks, every forked
record equals, message for message (compare_bags), the record of the same run made from tick 0
(`--no-fork`), and so do the tables; the checkpoints are removed;
(3) kept prefixes: an ideal sweep with `--save-prefix half` keeps each run's checkpoint at half the run,
and a later sweep that reuses those runs (--reuse, with a GP-DPO parameter CRW does not read, as the
paper's time-varying file has) forks every step_up run from them; its records equal those of the same
runs made from tick 0, and the kept checkpoints stay; a bad --save-prefix is refused;
(2) SLURM resubmission: on the one-node cluster of test/sweep/slurm_cluster.sh with `--time 1` (a minute,
SLURM's least), a run that takes longer is stopped at the limit, the sweep submits it again, it
continues from its last checkpoint (`checkpoint_every:=`, `resume:=`), and its record equals the one
run_experiment makes without stopping. The run's length is chosen from two timed short runs, so that
it takes about five minutes (five time limits) on this machine as it is now;
(4) a controller that cannot be checkpointed (the Levy example) is never forked: its step_up run starts
from tick 0 while CRW's forks, and the sweep completes; (5) run_one.sh starts a fork whose source saved no
checkpoint from tick 0, and passes resume:= for a checkpoint that exists."""
import sys
import glob
import os
import subprocess
import tempfile
import time
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from root_only import needs_root, rosrun  # noqa: E402
from graph_helpers import removed_at_exit, write  # noqa: E402
from sweep_helpers import experiment_text  # noqa: E402
from swarm_forage.sweep import jobs  # noqa: E402

SWEEP = ['rosrun', 'swarm_forage', 'sweep']
CLUSTER = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'slurm_cluster.sh')
CONDITIONS = 'conditions:\n  - {waveform: "null"}\n'
STEP_UPS = '  - {waveform: step_up, beta: [0.2, 0.8], alpha: -1}\n'
FORKS = experiment_text('forks', [8], 3000, 500) + CONDITIONS + STEP_UPS + \
    '  - {waveform: step_down, beta: 0.4, alpha: -1}\n'
# The ideal runs of one controller, then the same family with step_up runs (and a parameter CRW does not read).
PREFIX_IDEAL = experiment_text('kept_ideal', [8], 3000, 500, controllers=('crw',)) + CONDITIONS
PREFIX_STEPS = experiment_text('kept_steps', [8], 3000, 500, controllers=('crw',)) + CONDITIONS + STEP_UPS + \
    'params: {gp_dpo/estimates: time_varying}\n'
LEVY = 'swarm_forage_examples/levy'  # its batch has no persist(): not checkpointable
UNSAVED = experiment_text('unsaved', [4], 600, 300, controllers=('crw', LEVY), runs=1) + CONDITIONS + \
    '  - {waveform: step_up, beta: 0.5, alpha: -1}\n'


def run(cmd, **kw):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, **kw)


def table(out, name):
    with open(os.path.join(out, 'tables', name)) as f:
        return f.read()


class Checkpoints(unittest.TestCase):
    def setUp(self):
        self.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_ckpt_sweep_'))
        help_text = run(['rosrun', 'swarm_forage', 'run_experiment', '--help']).stdout
        self.assertIn('resume', help_text, 'this build\'s run_experiment has no save_at/resume')

    def test_1_forked_step_up_runs_equal_runs_from_tick_0(self):
        spec = write(self.tmp, 'forks.yaml', FORKS)
        forked, plain = os.path.join(self.tmp, 'forked'), os.path.join(self.tmp, 'plain')
        dry = run(SWEEP + [spec, '--out', forked, '--dry-run'], timeout=600)
        self.assertEqual(dry.returncode, 0, dry.stdout)
        # Per controller and seed: the ideal run saves at alpha, both step_up runs start from it.
        self.assertIn('forks: 8 of the runs to do start from 4 checkpoints', dry.stdout)
        self.assertIn('forks=8', dry.stdout)
        proc = run(SWEEP + [spec, '--out', forked, '-j', '2'], timeout=900)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        with open(os.path.join(forked, 'forks.tsv')) as f:
            extra = f.read()
        self.assertEqual(extra.count('resume:='), 8, extra)
        self.assertEqual(extra.count('save_at:=1500'), 4, extra)
        self.assertEqual(os.listdir(os.path.join(forked, 'checkpoints')), [], 'used checkpoints are removed')
        proc = run(SWEEP + [spec, '--out', plain, '-j', '2', '--no-fork'], timeout=900)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertNotIn('of the runs to do start from', proc.stdout)  # the plan's fork line
        same = run(['rosrun', 'swarm_forage', 'compare_bags', os.path.join(forked, 'runs'), os.path.join(plain, 'runs'),
                    '--ignore', '/world/provenance'], timeout=600)
        self.assertEqual(same.returncode, 0, same.stdout)
        self.assertEqual(same.stdout.count('identical'), 16, same.stdout)
        for name in ('series.csv', 'flexibility.csv', 'bootstrap.csv'):
            self.assertEqual(table(forked, name), table(plain, name), name)

    def test_4_a_stopped_sweep_forks_from_the_checkpoint_it_saved_and_removes_it(self):
        """A call stopped after an ideal run saved its checkpoint and before its forks ran (made here by
        hand: the ideal run's words from runs.tsv with save_at:=): the next call forks the step_up runs from
        that checkpoint (it saves no other), their records equal the ones made before, and it is removed."""
        spec = write(self.tmp, 'stopped.yaml', PREFIX_STEPS.replace('runs: 2', 'runs: 1'))
        out = os.path.join(self.tmp, 'stopped')
        first = run(SWEEP + [spec, '--out', out, '-j', '2'], timeout=900)
        self.assertEqual(first.returncode, 0, first.stdout)
        with open(os.path.join(out, 'runs.tsv')) as f:
            plan = [line.rstrip('\n').split('\t') for line in f]
        (ideal,) = [p for p in plan if 'waveform:=null' in p]
        before = os.path.join(self.tmp, 'before')
        os.mkdir(before)
        for p in plan:
            if p is not ideal:  # the step_up records: as if the stopped call never made them
                os.rename(os.path.join(out, 'runs', p[0] + '.bag'), os.path.join(before, p[0] + '.bag'))
        saved = os.path.join(out, 'checkpoints', ideal[0] + '_at1500.checkpoint')
        made = run(['rosrun', 'swarm_forage', 'run_experiment'] + ideal[1:] +
                   ['save_at:=1500', 'save:=' + saved, 'compression:=bz2', 'record_every:=3000',
                    'bag:=' + os.path.join(self.tmp, 'ideal_again.bag')],
                   timeout=600)
        self.assertEqual(made.returncode, 0, made.stdout)
        again = run(SWEEP + [spec, '--out', out, '-j', '2'], timeout=900)
        self.assertEqual(again.returncode, 0, again.stdout)
        self.assertIn('forks: 2 of the runs to do start from 1 checkpoints', again.stdout)
        with open(os.path.join(out, 'forks.tsv')) as f:
            extra = f.read()
        self.assertNotIn('save_at:=', extra)  # the ideal run is done: the stopped call's checkpoint serves
        self.assertEqual(extra.count('resume:=' + saved), 2, extra)
        self.assertEqual(os.listdir(os.path.join(out, 'checkpoints')), [], 'a spent checkpoint is removed')
        same = run(['rosrun', 'swarm_forage', 'compare_bags', before, os.path.join(out, 'runs'),
                    '--ignore', '/world/provenance'], timeout=600)
        self.assertEqual(same.stdout.count('identical'), 2, same.stdout)

    def test_3_step_up_runs_fork_from_the_checkpoints_another_sweep_kept(self):
        ideal_spec, steps_spec = write(self.tmp, 'ideal.yaml', PREFIX_IDEAL), write(self.tmp, 'steps.yaml', PREFIX_STEPS)
        ideal, steps, plain = (os.path.join(self.tmp, n) for n in ('ideal', 'steps', 'plain'))
        for bad in ('0', '3000', 'third'):
            proc = run(SWEEP + [ideal_spec, '--out', ideal, '--save-prefix', bad], timeout=600)
            self.assertNotEqual(proc.returncode, 0, proc.stdout)
            self.assertIn('--save-prefix %s: give half' % bad, proc.stdout)
        proc = run(SWEEP + [ideal_spec, '--out', ideal, '-j', '2', '--save-prefix', 'half'], timeout=900)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('prefixes: 2 runs also save their state after tick 1500', proc.stdout)
        kept = sorted(glob.glob(os.path.join(ideal, 'checkpoints', '*_at1500.checkpoint')))
        self.assertEqual(len(kept), 2, proc.stdout)
        dry = run(SWEEP + [steps_spec, '--out', steps, '--reuse', ideal, '--dry-run'], timeout=600)
        self.assertEqual(dry.returncode, 0, dry.stdout)
        self.assertIn('forks: 4 of the runs to do start from 2 checkpoints', dry.stdout)  # every step_up run
        self.assertIn('2 of them kept by the sweep whose ideal runs are reused', dry.stdout)
        proc = run(SWEEP + [steps_spec, '--out', steps, '--reuse', ideal, '-j', '2'], timeout=900)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        with open(os.path.join(steps, 'forks.tsv')) as f:
            extra = f.read()
        self.assertEqual(extra.count('resume:=' + os.path.join(ideal, 'checkpoints')), 4, extra)
        self.assertNotIn('save_at:=', extra)
        self.assertEqual(sorted(glob.glob(os.path.join(ideal, 'checkpoints', '*'))), kept, 'kept checkpoints stay')
        proc = run(SWEEP + [steps_spec, '--out', plain, '-j', '2', '--no-fork'], timeout=900)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        same = run(['rosrun', 'swarm_forage', 'compare_bags', os.path.join(steps, 'runs'), os.path.join(plain, 'runs'),
                    '--ignore', '/world/provenance'], timeout=600)
        self.assertEqual(same.returncode, 0, same.stdout)
        self.assertEqual(same.stdout.count('identical'), 6, same.stdout)

    def test_4_a_controller_that_cannot_be_checkpointed_is_not_forked(self):
        spec = write(self.tmp, 'unsaved.yaml', UNSAVED)
        out = os.path.join(self.tmp, 'unsaved')
        dry = run(SWEEP + [spec, '--out', out, '--dry-run'], timeout=600)
        self.assertEqual(dry.returncode, 0, dry.stdout)
        self.assertIn('forks: 1 of the runs to do start from 1 checkpoints', dry.stdout)  # CRW's step_up run
        self.assertIn('forks: %s cannot be checkpointed: its step_up runs start from tick 0' % LEVY, dry.stdout)
        proc = run(SWEEP + [spec, '--out', out, '-j', '2'], timeout=900)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        with open(os.path.join(out, 'runs.tsv')) as f:
            words = {line.split('\t')[0]: line.rstrip('\n').split('\t')[1:] for line in f}
        levy = {k for k, w in words.items() if 'controller:=' + LEVY in w}
        self.assertEqual(len(levy), 2, words)
        with open(os.path.join(out, 'forks.tsv')) as f:
            extra = {line.split('\t')[0]: line.rstrip('\n').split('\t')[1:] for line in f}
        self.assertEqual(sorted(w.split(':=')[0] for ws in extra.values() for w in ws), ['resume', 'save', 'save_at'])
        self.assertFalse(levy & set(extra), extra)
        self.assertEqual([k for k in words if not os.path.isfile(os.path.join(out, 'runs', k + '.bag'))], [])

    def test_5_a_fork_without_its_source_checkpoint_runs_from_tick_0(self):
        out = os.path.join(self.tmp, 'one')
        os.makedirs(os.path.join(out, 'runs'))
        gone = os.path.join(out, 'checkpoints', 'gone.checkpoint')
        runs = [{'key': key, 'words': ['controller:=crw', 'arena:=32x16', 'n_robots:=4', 'seed:=%d' % seed,
                                       'ticks:=200', 'waveform:=step_up', 'beta:=0.5', 'alpha:=-1'], 'from_tick': 100}
                for seed, key in ((1, 'fork_a'), (2, 'fork_b'))]
        jobs.write_plan(out, runs, runs, {'ticks': 200}, False, 1,
                              {r['key']: ['resume:=' + gone] for r in runs})
        proc = run([os.path.join(out, 'run_one.sh'), 'fork_a'], timeout=300)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertTrue(os.path.isfile(os.path.join(out, 'runs', 'fork_a.bag')), proc.stdout)
        write(os.path.dirname(gone), 'gone.checkpoint', 'not a checkpoint')  # it exists now: resume:= it
        proc = run([os.path.join(out, 'run_one.sh'), 'fork_b'], timeout=300)
        self.assertEqual(proc.returncode, 2, proc.stdout)
        self.assertIn('resume: ', proc.stdout)
        self.assertFalse(os.path.exists(os.path.join(out, 'runs', 'fork_b.bag')))

    @needs_root('the one-node SLURM of test/sweep/slurm_cluster.sh')
    def test_2_a_slurm_job_stopped_at_its_time_limit_continues_from_its_checkpoint(self):
        def words_for(n):
            return ['controller:=crw', 'arena:=64x32', 'n_robots:=%d' % n, 'seed:=1', 'threads:=1']

        # The end joins the bag's segments in one pass (docs/runs-and-bags.md, Checkpoints), which must fit in a
        # time limit with the ticks since the last checkpoint: at most 40 s of it. The join's time per tick is
        # the difference of two probes' tails (from the last progress line to the exit) with the sweep's
        # compression, 10,000 and 30,000 ticks: what does not grow with the ticks (the last checkpoint's fsync on
        # a busy disk, the exit) cancels.
        def tail(probe_ticks):
            probe_bag = os.path.join(self.tmp, 'probe.bag')
            probe = subprocess.Popen(['rosrun', 'swarm_forage', 'run_experiment', 'ticks:=%d' % probe_ticks,
                                      'bag:=' + probe_bag, 'compression:=bz2', 'record_every:=%d' % probe_ticks,
                                      'checkpoint_every:=%d' % (probe_ticks // 2), 'progress:=%d' % probe_ticks]
                                     + words_for(512), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
            last = None
            for line in probe.stderr:
                if 'tick %d of' % probe_ticks in line:
                    last = time.time()
            self.assertEqual(probe.wait(), 0)
            for f in glob.glob(probe_bag + '*'):
                os.remove(f)
            return time.time() - last

        join_per_tick = max(tail(30000) - tail(10000), 1e-3) / 20000
        # At most 10^6, the top of record_every's range (the reference run records one snapshot).
        most = min(1000000, int(40.0 / join_per_tick)) // 1000 * 1000
        # Ticks for about 300 s here and now (five time limits), from the time per tick of two short runs
        # (their difference: start-up apart), whatever the load. Where the most ticks take less, the swarm
        # doubles (up to 4,096 robots, what 64x32 holds), so that a fast machine's run still outlasts its limit.
        n = 512
        while True:
            words = words_for(n)
            took = []
            for probe_ticks in (2000, 10000):
                start = time.time()
                probe = run(['rosrun', 'swarm_forage', 'run_experiment', 'ticks:=%d' % probe_ticks] + words,
                            timeout=600)
                self.assertEqual(probe.returncode, 0, probe.stdout)
                took.append(time.time() - start)
            per_tick = max(took[1] - took[0], 1e-3) / 8000
            if per_tick * most >= 300.0 or n >= 4096:
                break
            n *= 2
        ticks = min(most, max(20000, int(300.0 / per_tick) // 1000 * 1000))
        print('N = %d: per tick %.3g s, join per tick %.3g s: %d ticks' % (n, per_tick, join_per_tick, ticks))
        spec = write(self.tmp, 'long.yaml', 'name: long\narena: 64x32\ncontrollers: [crw]\nsizes: [%d]\nruns: 1\n'
                     'ticks: %d\nsample_interval: 1000\n' % (n, ticks))
        os.chmod(self.tmp, 0o755)  # munged runs as user munge: it must reach its folder
        cluster = os.path.join(self.tmp, 'cluster')
        env = dict(os.environ, SLURM_CONF=os.path.join(cluster, 'slurm.conf'),
                   SLURM_TEST_PORT=str(16850 + os.getpid() % 40))
        up = run([CLUSTER, 'start', cluster], env=env, timeout=120)
        try:
            self.assertEqual(up.returncode, 0, up.stdout)
            out = os.path.join(self.tmp, 'slurm')
            proc = run(SWEEP + [spec, '--out', out, '--slurm', '--time', '1', '--checkpoint-every', str(ticks // 20)],
                       env=env, timeout=1800)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            self.assertIn('checkpoints: 1 runs write one every %d ticks' % (ticks // 20), proc.stdout)
            self.assertIn('with a checkpoint: submission 2', proc.stdout)
            logs = ''
            for path in glob.glob(os.path.join(out, 'slurm', '*.out')):
                with open(path) as f:
                    logs += f.read()
            self.assertIn('TIME LIMIT', logs, 'the first array task was stopped by its time limit')
        finally:
            run([CLUSTER, 'stop', cluster], env=env, timeout=60)
        bags = glob.glob(os.path.join(out, 'runs', '*.bag'))
        self.assertEqual(len(bags), 1, bags)
        self.assertEqual(os.listdir(os.path.join(out, 'checkpoints')), [], 'the finished run\'s checkpoint is removed')
        whole = os.path.join(self.tmp, 'whole.bag')
        label = os.path.basename(bags[0])[:-4]
        ref = run(['rosrun', 'swarm_forage', 'run_experiment', 'ticks:=%d' % ticks, 'waveform:=null', 'bag:=' + whole,
                   'label:=' + label, 'compression:=bz2', 'record_every:=%d' % ticks] + words, timeout=1800)
        self.assertEqual(ref.returncode, 0, ref.stdout)
        same = run(['rosrun', 'swarm_forage', 'compare_bags', bags[0], whole, '--ignore', '/world/provenance'],
                   timeout=1800)  # a million ticks are two million messages, read twice per bag
        self.assertEqual(same.returncode, 0, same.stdout)


if __name__ == '__main__':
    rosrun('swarm_forage', 'sweep_checkpoints', Checkpoints)
