#!/usr/bin/env python3
"""A Python controller in a sweep next to CRW (docs/python-controllers.md): `--controllers` lists it, a
two-size sweep of it and CRW through `sweep` on GNU Parallel records every run complete, and its tables,
figures, report and recommend hold both; the same sweep as a SLURM array on a one-node SLURM records the same
runs and tables."""
import glob
import os
import subprocess
import sys

import rospkg
import rostest
import yaml

SWARM_FORAGE = rospkg.RosPack().get_path('swarm_forage')
sys.path.insert(0, os.path.join(SWARM_FORAGE, 'test', 'helpers'))
from root_only import needs_root  # noqa: E402
from run_helpers import (RunsCase, drawn_figures, report_text, sweep_groups, sweep_records, tiny_sweep,  # noqa: E402
                         tiny_sweep_text)
from tmp_files import write  # noqa: E402

KIND = 'swarm_forage_examples/numpy_crw'
TINY = tiny_sweep_text('numpy_crw_tiny', KIND)


class PythonSweep(RunsCase):
    PREFIX = 'swarm_forage_python_sweep_'

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
        out = os.path.join(self.tmp, 'sweep')
        tiny_sweep(self, self.run_cmd, write(self.tmp, 'tiny.yaml', TINY), out)
        recorded = {(info.controller, info.swarm_size) for info, _ in sweep_records(self, out)}
        self.assertEqual(recorded, {(c, n) for c in ('crw', KIND) for n in (8, 16)})
        self.assertEqual(sweep_groups(out), {(c, n): 1 for c in ('crw', KIND) for n in (8, 16)})

        figures = os.path.join(self.tmp, 'figures')
        drawn = drawn_figures(self, out, figures)
        for name in ('final_performance_32x16.png', 'scalability_32x16.png'):
            self.assertTrue(os.path.isfile(os.path.join(figures, 'sweep', name)), name)
            self.assertTrue({'CRW', 'numpy CRW'} <= drawn[name], (name, drawn[name]))
        self.assertIn('numpy CRW', report_text(self, out, figures, os.path.join(self.tmp, 'report.md'), self.run_cmd))

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
        spec = write(self.tmp, 'tiny.yaml', TINY)
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
