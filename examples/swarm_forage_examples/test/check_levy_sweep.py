#!/usr/bin/env python3
"""A plugin controller in a sweep next to CRW (docs/your-own-controller.md): a two-size, two-controller
sweep through `sweep` on GNU Parallel records every run, and its tables, figures and report hold both."""
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

LEVY = 'swarm_forage_examples/levy'
TINY = """name: levy_tiny
arena: 32x16
controllers: [crw, %s]
sizes: [8, 16]
runs: 1
ticks: 5000
sample_interval: 1000
""" % LEVY


class LevySweep(unittest.TestCase):
    def setUp(self):
        self.tmp = tempfile.mkdtemp(prefix='swarm_forage_levy_sweep_')
        self.addCleanup(shutil.rmtree, self.tmp, True)
        self.scripts = os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'scripts')

    def run_cmd(self, args, timeout=400):
        return subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)

    def test_sweep_tables_figures_and_report_hold_both_controllers(self):
        spec = os.path.join(self.tmp, 'tiny.yaml')
        with open(spec, 'w') as f:
            f.write(TINY)
        out = os.path.join(self.tmp, 'sweep')
        proc = self.run_cmd(['rosrun', 'swarm_forage', 'sweep', spec, '--out', out, '-j', '2'])
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertIn('4 runs (0 done, 4 to do)', proc.stdout)

        # Every run recorded whole, under its controller's name.
        bags = sorted(glob.glob(os.path.join(out, 'runs', '*.bag')))
        self.assertEqual(len(bags), 4, bags)
        recorded = set()
        for path in bags:
            with rosbag.Bag(path) as bag:
                info = [m for _, m, _ in bag.read_messages(topics=['/world/run_info'])][0]
                ends = [m for _, m, _ in bag.read_messages(topics=['/world/run_end'])]
                statuses = [m for _, m, _ in bag.read_messages(topics=['/swarm/status'])]
            self.assertTrue(ends and ends[0].complete, path)
            recorded.add((info.controller, info.swarm_size))
            if info.controller == LEVY:
                self.assertEqual(list(statuses[0].state_names),
                                 ['explore', 'pickup', 'transport', 'nest_wander', 'drop', 'leave_nest'], path)
        self.assertEqual(recorded, {(c, n) for c in ('crw', LEVY) for n in (8, 16)})

        # Tables: one group per controller and size.
        with open(os.path.join(out, 'tables', 'series.csv')) as f:
            groups = {(r['controller'], int(r['swarm_size'])): int(r['runs']) for r in csv.DictReader(f)}
        self.assertEqual(groups, {(c, n): 1 for c in ('crw', LEVY) for n in (8, 16)})
        for table in ('scalability', 'self_organization'):
            with open(os.path.join(out, 'tables', table + '.csv')) as f:
                valid = {r['controller'] for r in csv.DictReader(f) if r['valid'] == '1'}
            self.assertEqual(valid, {'crw', LEVY}, table)

        # Figures, drawn by the project's script: every labelled line of every figure, by its display name.
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
        for name in ('final_performance_32x16.png', 'scalability_32x16.png', 'self_organization_32x16.png'):
            self.assertTrue(os.path.isfile(os.path.join(figures, 'sweep', name)), name)
            self.assertTrue({'CRW', 'Levy'} <= drawn[name], (name, drawn[name]))
        self.assertTrue({'CRW, 32x16', 'Levy, 32x16'} <= drawn['performance_32x16.png'], drawn)

        # The report lists both.
        report = os.path.join(self.tmp, 'report.md')
        proc = self.run_cmd([sys.executable, os.path.join(self.scripts, 'paper_report.py'), '--ideal', out,
                             '--figures', figures, '--output', report])
        self.assertEqual(proc.returncode, 0, proc.stdout)
        with open(report) as f:
            text = f.read()
        self.assertIn('Levy', text)
        self.assertIn('CRW', text)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'levy_sweep', LevySweep)
