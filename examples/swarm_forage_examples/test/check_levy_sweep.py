#!/usr/bin/env python3
"""A plugin controller in a sweep next to CRW (docs/your-own-controller.md): a two-size, two-controller
sweep through `sweep` on GNU Parallel records every run, and its tables, figures and report hold both."""
import csv
import os
import subprocess
import sys

import rospkg
import rostest

sys.path.insert(0, os.path.join(rospkg.RosPack().get_path('swarm_forage'), 'test', 'helpers'))
from run_helpers import (RunsCase, drawn_figures, report_text, sweep_groups, sweep_records, tiny_sweep,  # noqa: E402
                         tiny_sweep_text)
from tmp_files import write  # noqa: E402

LEVY = 'swarm_forage_examples/levy'
TINY = tiny_sweep_text('levy_tiny', LEVY)


class LevySweep(RunsCase):
    PREFIX = 'swarm_forage_levy_sweep_'

    def run_cmd(self, args, timeout=400):
        return subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)

    def test_sweep_tables_figures_and_report_hold_both_controllers(self):
        out = os.path.join(self.tmp, 'sweep')
        tiny_sweep(self, self.run_cmd, write(self.tmp, 'tiny.yaml', TINY), out)

        # Every run recorded whole, under its controller's name.
        recorded = set()
        for info, status in sweep_records(self, out):
            recorded.add((info.controller, info.swarm_size))
            if info.controller == LEVY:
                self.assertEqual(list(status.state_names),
                                 ['explore', 'pickup', 'transport', 'nest_wander', 'drop', 'leave_nest'], info)
        self.assertEqual(recorded, {(c, n) for c in ('crw', LEVY) for n in (8, 16)})

        # Tables: one group per controller and size.
        self.assertEqual(sweep_groups(out), {(c, n): 1 for c in ('crw', LEVY) for n in (8, 16)})
        for table in ('scalability', 'self_organization'):
            with open(os.path.join(out, 'tables', table + '.csv')) as f:
                valid = {r['controller'] for r in csv.DictReader(f) if r['valid'] == '1'}
            self.assertEqual(valid, {'crw', LEVY}, table)

        # Figures, drawn by the project's script: every labelled line of every figure, by its display name.
        figures = os.path.join(self.tmp, 'figures')
        drawn = drawn_figures(self, out, figures)
        for name in ('final_performance_32x16.png', 'scalability_32x16.png', 'self_organization_32x16.png'):
            self.assertTrue(os.path.isfile(os.path.join(figures, 'sweep', name)), name)
            self.assertTrue({'CRW', 'Levy'} <= drawn[name], (name, drawn[name]))
        self.assertTrue({'CRW, 32x16', 'Levy, 32x16'} <= drawn['performance_32x16.png'], drawn)

        # The report lists both.
        text = report_text(self, out, figures, os.path.join(self.tmp, 'report.md'), self.run_cmd)
        self.assertIn('Levy', text)
        self.assertIn('CRW', text)


if __name__ == '__main__':
    rostest.rosrun('swarm_forage_examples', 'levy_sweep', LevySweep)
