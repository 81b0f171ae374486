#!/usr/bin/env python3
"""One form per idea: docs/nodes-and-parameters.md's tables and the launch files' argument docs agree with the
parameter table (`param_docs --check`, which fails on a drifted copy), the paper's controllers are named once and
are kinds of the registry, an arena is looked up by name once (run_experiment), and `sweep --graph` reads a launch
file's arguments as `forage` does. No master."""
import glob
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import yaml

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from tmp_files import removed_at_exit, write  # noqa: E402

from swarm_forage.experiment import file as experiment_file  # noqa: E402
from swarm_forage.graph import forage, launch_args, param_docs  # noqa: E402
from swarm_forage.recommend import target  # noqa: E402
from swarm_forage.study import claims  # noqa: E402
from swarm_forage.sweep import steps  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
TOOL = os.path.join(ROOT, 'scripts', 'param_docs')
DOC = os.path.join(ROOT, 'docs', 'nodes-and-parameters.md')


def run(args):
    return subprocess.run([sys.executable, TOOL] + args, cwd=ROOT, capture_output=True, text=True)


def python_files():
    """The package's modules, the scripts and the benchmarks' Python."""
    return [p for p in glob.glob(os.path.join(ROOT, 'src', 'swarm_forage', '**', '*.py'), recursive=True) +
            glob.glob(os.path.join(ROOT, 'scripts', '*')) + glob.glob(os.path.join(ROOT, 'bench', '*.py'))
            if os.path.isfile(p)]


class ParamDocs(unittest.TestCase):
    def setUp(self):
        self.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_param_docs_'))

    def test_1_the_docs_and_launch_files_are_current(self):
        proc = run(['--check'])
        self.assertEqual(proc.returncode, 0, proc.stderr)
        with open(DOC) as f:
            text = f.read()
        for name in ('world_node', 'controller_node', 'environment_node', 'metrics_node', 'run_experiment',
                     'foraging.launch'):
            self.assertIn(param_docs.BEGIN % name, text)
        self.assertIn('| `n_robots` | 64 | a whole number in [1, 10000000]', text)

    def test_2_a_drifted_doc_table_fails_and_write_remakes_it(self):
        with open(DOC) as f:
            good = f.read()
        for old, new, table in (('| `n_robots` | 64 |', '| `n_robots` | 65 |', 'world_node'),
                                ('a number in [0.01, 3600]', 'a number in [0.01, 600]', 'world_node'),
                                ('| `dtw_band` |', '| `dtw_bands` |', 'metrics_node'),
                                ('| `record` | `false` |', '| `record` | `true` |', 'foraging.launch')):
            with self.subTest(table=table, edit=new):
                self.assertTrue(old in good, 'the doc lacks %s' % old)
                doc = write(self.tmp, 'doc.md', good.replace(old, new, 1))
                proc = run(['--check', '--doc', doc])
                self.assertEqual(proc.returncode, 1, proc.stdout)
                self.assertIn('the table %s is not what the parameter table makes' % table, proc.stderr)
                self.assertEqual(run(['--write', '--doc', doc]).returncode, 0)
                with open(doc) as f:
                    self.assertEqual(f.read(), good)
        doc = write(self.tmp, 'doc.md', good.replace(param_docs.BEGIN % 'metrics_node', ''))
        proc = run(['--check', '--doc', doc])
        self.assertEqual(proc.returncode, 1)
        self.assertIn('has no %s' % (param_docs.BEGIN % 'metrics_node'), proc.stderr)

    def test_3_a_drifted_launch_file_fails(self):
        launch = os.path.join(self.tmp, 'launch')
        shutil.copytree(os.path.join(ROOT, 'launch'), launch)
        path = os.path.join(launch, 'foraging.launch')
        with open(path) as f:
            text = f.read()
        for old, new in (('seed in [0, 2147483647]', 'seed in [0, 100]'),
                         ('controller kind: crw, dpo, gp_dpo', 'controller kind: crw, dpo'),
                         ('<param name="n_robots"', '<param name="n_robot"'),
                         ('name="markers_rate" default="5"', 'name="markers_rate" default="6"'),
                         ('(node default: 0)"/>\n  <arg name="ticks"', '(node default: 1)"/>\n  <arg name="ticks"')):
            self.assertTrue(old in text, 'foraging.launch lacks %s' % old)
            text = text.replace(old, new, 1)
        write(launch, 'foraging.launch', text)
        proc = run(['--check', '--launch', launch])
        self.assertEqual(proc.returncode, 1, proc.stdout)
        for words in ('argument seed: its doc says [0, 100] where ~seed is a whole number in [0, 2147483647]',
                      'argument controller: its doc leaves out gp_dpo of ~controller',
                      'argument n_robots sets ~n_robot, which is not a parameter of world_node',
                      'argument markers_rate: default 6 where ~markers_rate defaults to 5',
                      'argument seed: its doc says (node default: 1) where ~seed defaults to 0'):
            self.assertIn(words, proc.stderr)

    def test_4_the_paper_controllers_are_named_once_and_the_condition_keys_are_the_tables(self):
        table = param_docs.load_table()
        controller = [r for r in table['parameters'] if r['name'] == 'controller'][0]
        self.assertTrue(set(claims.PAPER) <= set(controller['choices']), controller['choices'])
        copies = [p for p in python_files() if "'crw', 'dpo', 'gp_dpo'" in open(p, errors='replace').read()]
        self.assertEqual([os.path.relpath(p, ROOT) for p in copies], ['src/swarm_forage/study/claims.py'])
        # An experiment file's condition keys (their order is the record key's) are the table's condition rows.
        self.assertEqual(set(experiment_file.CONDITION_KEYS),
                         {r['name'] for r in table['parameters'] if r['type'] == 'condition'})

    def test_5_an_arena_is_looked_up_by_name_in_one_place(self):
        proc = subprocess.run(['rosrun', 'swarm_forage', 'run_experiment', '--arenas'], capture_output=True, text=True)
        self.assertEqual(proc.returncode, 0, proc.stderr)
        listing = yaml.safe_load(proc.stdout)
        self.assertEqual([a['arena'] for a in listing], ['32x16', '64x32', '96x48'])
        for a in listing:
            self.assertTrue(os.path.isfile(a['file']), a)
        self.assertEqual(target.arenas()['64x32'], (64.0, 32.0))
        for p in python_files():
            if not p.startswith(os.path.join(ROOT, 'bench')):
                self.assertNotIn("'arenas'", open(p, errors='replace').read(), p)

    def test_6_sweep_and_forage_read_a_launch_files_arguments_alike(self):
        graph = os.path.join(ROOT, 'launch', 'foraging.launch')
        self.assertEqual(steps.graph_args(), set(launch_args.arg_names(graph)))
        mine = write(self.tmp, 'mine.launch', '<launch>\n  <arg name="extra" default="1"/>\n'
                     '  <include file="%s" pass_all_args="true">\n    <arg name="seed" value="3"/>\n'
                     '  </include>\n</launch>\n' % graph)
        names = launch_args.arg_names(mine)
        self.assertIn('extra', names)
        self.assertIn('n_robots', names)
        self.assertNotIn('seed', names)  # the include sets it
        self.assertEqual(names, [a.get('name') for a in forage.declared_args(mine)])


if __name__ == '__main__':
    unittest.main()
