#!/usr/bin/env python3
"""A Python controller in a sweep next to CRW (docs/python-controllers.md): `--controllers` lists it, a
two-size sweep of it and CRW through `sweep` on GNU Parallel records every run complete, and its tables,
figures, report and recommend hold both; the same sweep as a SLURM array on a one-node SLURM records the same
runs and tables."""
import csv
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import rosbag
import rospkg
import rostest
import yaml

SWARM_FORAGE = rospkg.RosPack().get_path('swarm_forage')
sys.path.insert(0, os.path.join(SWARM_FORAGE, 'test', 'helpers'))
from root_only import needs_root  # noqa: E402

KIND = 'swarm_forage_examples/numpy_crw'
TINY = """name: numpy_crw_tiny
arena: 32x16
controllers: [crw, %s]
sizes: [8, 16]
runs: 1
ticks: 5000
sample_interval: 1000
""" % KIND


class PythonSweep(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_python_sweep_')
        self.addCleanup(shutil.rmtree, self.tmp, True)
        self.scripts = os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'scripts')

    def run_cmd(self, args, timeout=600):
        # In the test's folder: recommend draws its figure into the current one.
        return subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout,
                              cwd=self.tmp)

    def test_listing(self):
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--controllers'], stdout=subprocess.PIPE,
                              stderr=subprocess.PIPE, text=True, timeout=300)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        kinds = {k['name']: k for k in yaml.safe_load(proc.stdout)}
        k = kinds[KIND]
        self.assertEqual((k['display_name'], k['colour'], k['checkpointable'], k['package'], k['light_only_carrying']),
                         ('numpy CRW', 'tab:cyan', True, 'swarm_forage_examples', True))
        self.assertEqual(k['constants'], [KIND])
        self.assertEqual(k['defaults'], os.path.join(rospkg.RosPack().get_path('swarm_forage_examples'), 'config',
                                                     'numpy_crw.yaml'))
        self.assertIn('swarm_forage_examples/numpy_forager', kinds)

    def test_sweep_tables_figures_report_and_recommend_hold_both_controllers(self):
        spec = os.path.join(self.tmp, 'tiny.yaml')
        with open(spec, 'w') as f:
            f.write(TINY)
        out = os.path.join(self.tmp, 'sweep')
        proc = self.run_cmd(['rosrun', 'swarm_forage', 'sweep', spec, '--out', out, '-j', '2'])
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('4 runs (0 done, 4 to do)', proc.stdout)
        bags = sorted(glob.glob(os.path.join(out, 'runs', '*.bag')))
        self.assertEqual(len(bags), 4, bags)
        recorded = set()
        for path in bags:
            with rosbag.Bag(path) as bag:
                info = [m for _, m, _ in bag.read_messages(topics=['/world/run_info'])][0]
                ends = [m for _, m, _ in bag.read_messages(topics=['/world/run_end'])]
            self.assertTrue(ends and ends[0].complete, path)
            recorded.add((info.controller, info.swarm_size))
        self.assertEqual(recorded, {(c, n) for c in ('crw', KIND) for n in (8, 16)})

        with open(os.path.join(out, 'tables', 'series.csv')) as f:
            groups = {(r['controller'], int(r['swarm_size'])): int(r['runs']) for r in csv.DictReader(f)}
        self.assertEqual(groups, {(c, n): 1 for c in ('crw', KIND) for n in (8, 16)})

        from swarm_forage.figures import sweep as plot_sweep
        drawn = {}
        original = plot_sweep.save

        def save(fig, folder, name):
            drawn[name] = {t.get_text() for ax in fig.axes for t in
                           ([ax.title] + (ax.get_legend().get_texts() if ax.get_legend() else []))}
            return original(fig, folder, name)

        plot_sweep.save = save
        figures = os.path.join(self.tmp, 'figures')
        self.assertEqual(plot_sweep.main([out, '--output', figures]), 0)
        for name in ('final_performance_32x16.png', 'scalability_32x16.png'):
            self.assertTrue(os.path.isfile(os.path.join(figures, 'sweep', name)), name)
            self.assertTrue({'CRW', 'numpy CRW'} <= drawn[name], (name, drawn[name]))

        report = os.path.join(self.tmp, 'report.md')
        proc = self.run_cmd([sys.executable, os.path.join(self.scripts, 'paper_report.py'), '--ideal', out,
                             '--figures', figures, '--output', report])
        self.assertEqual(proc.returncode, 0, proc.stdout)
        with open(report) as f:
            self.assertIn('numpy CRW', f.read())

        target = os.path.join(self.tmp, 'target.yaml')
        with open(target, 'w') as f:
            f.write('name: tiny\narena: 32x16\nrobots: 16\nweights: {performance: 1}\n')
        proc = self.run_cmd(['rosrun', 'swarm_forage', 'recommend', target, out])
        self.assertIn(proc.returncode, (0, 1), proc.stdout)
        self.assertIn(KIND, proc.stdout)

    @needs_root('the one-node SLURM of slurm_cluster.sh', sudo=True)
    def test_slurm_array_records_the_local_runs(self):
        """The numpy CRW beside CRW as a SLURM array (munged, slurmctld, slurmd of its own): each array task
        starts the embedded interpreter in its own job, and the runs and tables equal GNU Parallel's."""
        spec = os.path.join(self.tmp, 'tiny.yaml')
        with open(spec, 'w') as f:
            f.write(TINY)
        local, slurm = os.path.join(self.tmp, 'local'), os.path.join(self.tmp, 'slurm')
        proc = self.run_cmd(['rosrun', 'swarm_forage', 'sweep', spec, '--out', local, '-j', '2'])
        self.assertEqual(proc.returncode, 0, proc.stdout)
        os.chmod(self.tmp, 0o755)  # munged runs as user munge: it must reach its folder
        cluster = os.path.join(self.tmp, 'cluster')
        script = os.path.join(SWARM_FORAGE, 'test', 'sweep', 'slurm_cluster.sh')
        env = dict(os.environ, SLURM_CONF=os.path.join(cluster, 'slurm.conf'),
                   SLURM_TEST_PORT=str(16950 + os.getpid() % 40))
        sudo = [] if os.geteuid() == 0 else ['sudo', '-n', '-E']
        start = subprocess.run(sudo + [script, 'start', cluster], env=env, stdout=subprocess.PIPE,
                               stderr=subprocess.STDOUT, text=True, timeout=120)
        try:
            self.assertEqual(start.returncode, 0, start.stdout)
            proc = subprocess.run(['rosrun', 'swarm_forage', 'sweep', spec, '--out', slurm, '--slurm', '--chunk', '2'],
                                  env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=600,
                                  cwd=self.tmp)
            self.assertEqual(proc.returncode, 0, proc.stdout)
            self.assertIn('submitting', proc.stdout)
        finally:
            subprocess.run(sudo + [script, 'stop', cluster], env=env, timeout=60)
        names = lambda d: sorted(os.path.basename(p) for p in glob.glob(os.path.join(d, 'runs', '*.bag')))
        self.assertEqual(len(names(slurm)), 4)
        self.assertEqual(names(slurm), names(local))
        for table in ('series', 'scalability'):
            with open(os.path.join(slurm, 'tables', table + '.csv')) as a, \
                    open(os.path.join(local, 'tables', table + '.csv')) as b:
                self.assertEqual(a.read(), b.read(), table)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'python_sweep', PythonSweep)
