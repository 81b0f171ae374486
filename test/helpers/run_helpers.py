"""What the tests of a controller's runs share: a command's exit code and words, a test case with a folder of
its own and records made in it, the graph and headless runs of one controller compared, a run stopped by
SIGTERM after a checkpoint, and a tiny sweep of a controller beside CRW with its figures and report."""
import csv
import glob
import os
import shutil
import signal
import subprocess
import sys
import tempfile
import unittest

import rosbag

RUN = ['rosrun', 'swarm_forage', 'run_experiment']
COMPARE = ['rosrun', 'swarm_forage', 'compare_bags', '--ignore', '/world/provenance']
# A graph run that records its bag and starts at once, without metrics_node.
GRAPH = ['metrics:=false', 'wait_for_subscribers:=0', 'record:=true']
SCRIPTS = os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', '..', 'scripts')


def run(*cmd, timeout=600):
    """(exit code, everything it said) of a command."""
    proc = subprocess.run(list(cmd), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)
    return proc.returncode, proc.stdout


class RunsCase(unittest.TestCase):
    """A test case with a folder of its own (`PREFIX`), removed at its end, to record runs in."""
    PREFIX = 'swarm_forage_runs_'
    TIMEOUT = 600

    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix=self.PREFIX)
        self.addCleanup(shutil.rmtree, self.tmp, True)

    def path(self, name):
        return os.path.join(self.tmp, name)

    def bag(self, name, *cmd):
        """The record of `cmd` with bag:= NAME.bag in the test's folder; the command must succeed."""
        path = self.path(name + '.bag')
        code, out = run(*(list(cmd) + ['bag:=' + path]), timeout=self.TIMEOUT)
        self.assertEqual(code, 0, out[-3000:])
        return path

    def assertSameRun(self, a, b):
        code, out = run(*(COMPARE[:3] + [a, b] + COMPARE[3:]), timeout=self.TIMEOUT)
        self.assertEqual(code, 0, out)
        self.assertIn('identical', out)

    def assertOtherRun(self, a, b):
        code, out = run(*(COMPARE[:3] + [a, b] + COMPARE[3:]), timeout=self.TIMEOUT)
        self.assertEqual(code, 1, out)

    def assertModesAgree(self, headless, words, kind):
        """The graph's and the nodelet graph's records of `words` equal each other, and the headless record
        `headless` but for header.seq; 1,100 robots of `kind`, a range stepped in parts on worker threads (512
        robots or more a part), record the same run on one thread and on two."""
        from check_headless_identity import messages  # header.seq cleared: a graph's differs
        graph = self.bag('graph', 'rosrun', 'swarm_forage', 'forage', *(GRAPH + words))
        nodelet = self.bag('nodelet', 'rosrun', 'swarm_forage', 'forage', 'nodelet:=true', *(GRAPH + words))
        self.assertSameRun(graph, nodelet)
        a, b = messages(headless), messages(graph)
        del a['/world/provenance'], b['/world/provenance']
        self.assertEqual(sorted(a), sorted(b))
        for topic in a:
            self.assertEqual(a[topic], b[topic], topic)
        big = ['controller:=' + kind, 'n_robots:=1100', 'seed:=2', 'ticks:=300']
        one = self.bag('one_thread', *RUN, 'threads:=1', *big)
        two = self.bag('two_threads', *RUN, 'threads:=2', *big)
        self.assertSameRun(one, two)


def stop_after_checkpoint(test, args):
    """Starts run_experiment with `args` (checkpoint_every:=300), stops it by SIGTERM once tick 300's checkpoint
    is written, and checks that it exits 1 naming the resume:= that continues it; returns what it said last."""
    # A progress line a tick into a pipe the test stops reading: the run gets at most a pipe's worth of lines
    # (about 1,000 ticks) ahead, so it is still running when the signal comes, however busy the machine.
    p = subprocess.Popen(RUN + args + ['progress:=1'], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    for line in p.stderr:
        if 'tick 301 of' in line:  # the checkpoint of tick 300 is written
            break
    p.send_signal(signal.SIGTERM)
    rest = p.stderr.read()
    test.assertEqual(p.wait(), 1, rest[-2000:])
    bag = next(a[len('bag:='):] for a in args if a.startswith('bag:='))
    test.assertIn('resume:=%s.checkpoint continues it' % bag, rest)
    return rest


def tiny_sweep_text(name, kind):
    """An experiment file: `kind` beside CRW at 8 and 16 robots in 32x16, one seed of 5,000 ticks."""
    return ('name: %s\narena: 32x16\ncontrollers: [crw, %s]\nsizes: [8, 16]\nruns: 1\nticks: 5000\n'
            'sample_interval: 1000\n' % (name, kind))


def tiny_sweep(test, run_cmd, spec, out):
    """Sweeps the experiment file `spec` into `out` on GNU Parallel, two runs at a time: its 4 runs, none done
    before."""
    proc = run_cmd(['rosrun', 'swarm_forage', 'sweep', spec, '--out', out, '-j', '2'])
    test.assertEqual(proc.returncode, 0, proc.stdout)
    test.assertIn('4 runs (0 done, 4 to do)', proc.stdout)


def sweep_groups(out):
    """{(controller, N): runs} of the sweep's series table."""
    with open(os.path.join(out, 'tables', 'series.csv')) as f:
        return {(r['controller'], int(r['swarm_size'])): int(r['runs']) for r in csv.DictReader(f)}


def sweep_records(test, out):
    """Every record of the sweep in `out` (4 of them), each complete: [(run_info, its first swarm/status)]."""
    bags = sorted(glob.glob(os.path.join(out, 'runs', '*.bag')))
    test.assertEqual(len(bags), 4, bags)
    found = []
    for path in bags:
        with rosbag.Bag(path) as bag:
            info = [m for _, m, _ in bag.read_messages(topics=['/world/run_info'])][0]
            ends = [m for _, m, _ in bag.read_messages(topics=['/world/run_end'])]
            statuses = [m for _, m, _ in bag.read_messages(topics=['/swarm/status'])]
        test.assertTrue(ends and ends[0].complete, path)
        found.append((info, statuses[0] if statuses else None))
    return found


def drawn_figures(test, out, figures):
    """{figure file: the texts of its titles and legends} of the project's figures of the sweep in `out`."""
    from swarm_forage.figures import sweep as plot_sweep
    drawn = {}
    original = plot_sweep.save

    def save(fig, folder, name):
        drawn[name] = {t.get_text() for ax in fig.axes for t in
                       ([ax.title] + (ax.get_legend().get_texts() if ax.get_legend() else []))}
        return original(fig, folder, name)

    plot_sweep.save = save
    try:
        test.assertEqual(plot_sweep.main([out, '--output', figures]), 0)
    finally:
        plot_sweep.save = original
    return drawn


def report_text(test, out, figures, report, run_cmd):
    """The text of paper_report.py's report of the sweep in `out`, run through `run_cmd`."""
    proc = run_cmd([sys.executable, os.path.join(SCRIPTS, 'paper_report.py'), '--ideal', out, '--figures', figures,
                    '--output', report])
    test.assertEqual(proc.returncode, 0, proc.stdout)
    with open(report) as f:
        return f.read()
