#!/usr/bin/env python3
"""`recommend` on a small synthetic library of hand-written tables (the formats of
src/core/metrics/metric_tables.cpp and tables/bootstrap.csv): its ranking equals the one computed by hand
below, the model fit recovers a, b, c, missing measurements are named per controller with their `sweep`
command, and each bad input gives its message and exit code, writing nothing. Then the committed study
(docs/paper_96) as a fresh clone has it, and `paper --publish`'s copy read back."""
import csv
import glob
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from tmp_files import removed_at_exit, write  # noqa: E402
from swarm_forage.recommend import model

RECOMMEND = ['rosrun', 'swarm_forage', 'recommend']
HEAD = 'controller,arena,waveform,beta,environment,'
TAIL = ',1000,abcd1234'
# Ideal final P, e and Z; (R, A) under step_down beta 0.4, by (controller, N). 32x16, 2 seeds, N = 4 and 8.
P = {('crw', 4): 20, ('crw', 8): 44, ('dpo', 4): 30, ('dpo', 8): 36}
E = {('crw', 8): 0.5, ('dpo', 8): 1.5}
Z = {('crw', 8): 0.4, ('dpo', 8): 0.6}
RA = {('crw', 4): (10, 8), ('crw', 8): (20, 12), ('dpo', 4): (5, 4), ('dpo', 8): (40, 30)}
# By hand, weights performance 2, scalability 1, reactivity 1, adaptability 1 (sum 5), min-max per criterion:
#   s_P = (P - 20)/24: crw4 0, crw8 1, dpo4 0.41667, dpo8 0.66667
#   s_e (lower better, undefined at the smallest N = 0): crw8 1, dpo8 0, crw4 0, dpo4 0
#   R and A are scored per block (R/P, A/P, P the group's ideal final P): crw4 0.5, 0.4; crw8 0.45455, 0.27273;
#   dpo4 0.16667, 0.13333; dpo8 1.11111, 0.83333
#   s_R = (1.11111 - R/P)/(1.11111 - 0.16667): crw4 0.64706, crw8 0.69519, dpo4 1, dpo8 0
#   s_A = (0.83333 - A/P)/(0.83333 - 0.13333): crw4 0.61905, crw8 0.80087, dpo4 1, dpo8 0
#   score: crw8 (2 + 1 + 0.69519 + 0.80087)/5 = 0.899; dpo4 (0.83333 + 0 + 1 + 1)/5 = 0.567;
#          dpo8 (1.33333 + 0 + 0 + 0)/5 = 0.267; crw4 (0 + 0 + 0.64706 + 0.61905)/5 = 0.253
RANKING = [('crw', 8, '0.899'), ('dpo', 4, '0.567'), ('dpo', 8, '0.267'), ('crw', 4, '0.253')]
TARGET = """name: synthetic
arena: 32x16
robots: %d
conditions: {waveform: %s, beta: %s}
weights: {performance: 2, scalability: 1, reactivity: 1, adaptability: 1}
"""


def env(w, b):
    return '"%s"' % ('ideal' if w == 'null' else '%s(%g)' % (w, b))


def tables(folder, arena, groups, e, z, ra=None, waveform='step_down', beta=0.4, runs=2, plan=True):
    """Writes FOLDER/tables/*.csv (and a plan runs.tsv with a record per run) for ideal groups {(c, N): P}."""
    t = os.path.join(folder, 'tables')
    os.makedirs(os.path.join(folder, 'runs'))
    os.makedirs(t)
    series = ['controller,arena,swarm_size,waveform,beta,alpha,runs,sample,tick_end,P_mean,P_ci95,p_mean,p_ci95,'
              'n_ca_mean,n_ca_ci95,sample_interval,identity']
    sc, so, fx = [HEAD + 'N1,N2,N_used,runs,phi,e,valid,status' + ',sample_interval,identity'], \
        [HEAD + 'm_prev,m_i,runs,theta_Z,Z_sum,Z_mean,valid,status,sample_interval,identity'], \
        [HEAD + 'N,runs,R,A,valid,status,sample_interval,identity']
    plan_rows = []
    conds = [('null', 0)] + ([(waveform, beta)] if ra else [])
    for (c, n), p in sorted(groups.items()):
        for w, b in conds:
            for s in (0, 1):  # two samples: the last is the final
                series.append('%s,%s,%d,%s,%g,-1,%d,%d,%d,%g,%g,1,0,0,0,1000,abcd1234'
                              % (c, arena, n, w, b, runs, s, 999 + 1000 * s, p * (s + 1) / 2.0, p * 0.1 * s))
            for seed in range(1, runs + 1):
                key = '%s_n%d_%s_seed%d_h' % (c, n, w, seed)
                plan_rows.append('%s\tcontroller:=%s\tn_robots:=%d\tseed:=%d\tticks:=1500' % (key, c, n, seed))
        if (c, n) in e:
            sc.append('%s,%s,null,0,"ideal",%d,%d,%d,%d,1,%g,1,"ok"%s' % (c, arena, n // 2, n, n // 2, runs, e[(c, n)], TAIL))
            so.append('%s,%s,null,0,"ideal",%d,%d,%d,0,1,%g,1,"ok"%s' % (c, arena, n // 2, n, runs, z[(c, n)], TAIL))
        if ra:
            fx.append('%s,%s,%s,%g,%s,%d,%d,%g,%g,1,"ok"%s' % (c, arena, waveform, beta, env(waveform, beta), n, runs,
                                                              ra[(c, n)][0], ra[(c, n)][1], TAIL))
    for name, rows in (('series', series), ('scalability', sc), ('self_organization', so), ('flexibility', fx)):
        write(t, name + '.csv', '\n'.join(rows) + '\n')
    if plan:
        write(folder, 'runs.tsv', '\n'.join(plan_rows) + '\n')
        for row in plan_rows:
            write(os.path.join(folder, 'runs'), row.split('\t')[0] + '.bag', '')
    return folder


class Recommend(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_recommend_'))
        cls.ideal = tables(os.path.join(cls.tmp, 'ideal_32x16'), '32x16', P, E, Z, RA)
        # A bootstrap of crw N = 8's P: draws 1 ... 4 = 40, 42, 46, 48 -> 95 % interval [40.15, 47.85].
        rows = ['draw,controller,arena,waveform,beta,environment,N,runs,P,e,Z,R,A,sample_interval,identity']
        rows += ['%d,crw,32x16,null,0,"ideal",8,2,%g,,,,,1000,abcd1234' % (d, p)
                 for d, p in enumerate((44, 40, 42, 46, 48))]
        write(os.path.join(cls.ideal, 'tables'), 'bootstrap.csv', '\n'.join(rows) + '\n')

    def run_recommend(self, text, *folders, output=True):
        path = write(self.tmp, 'target.yaml', text)
        out = os.path.join(tempfile.mkdtemp(dir=self.tmp), 'out', 'recommend.txt')
        args = RECOMMEND + [path] + list(folders or [self.ideal]) + (['--output', out] if output else [])
        proc = subprocess.run(args, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=self.tmp,
                              timeout=120)
        return proc, out

    def test_1_ranks_as_computed_by_hand(self):
        proc, out = self.run_recommend(TARGET % (8, 'step_down', 0.4))
        self.assertEqual(proc.returncode, 0, proc.stderr + proc.stdout)
        lines = proc.stdout.splitlines()
        start = next(k for k, line in enumerate(lines) if line.split()[:2] == ['rank', 'controller']) + 2
        got = []
        for line in lines[start:start + 4]:
            w = line.split()
            got.append((w[1], int(w[2]), w[w.index('measured') - 1]))  # the score precedes the source
        self.assertEqual(got, RANKING, proc.stdout)
        self.assertIn('min-max', proc.stdout)
        self.assertIn('[40.15, 47.85]', proc.stdout)  # crw N = 8's bootstrap interval
        self.assertIn('Recommended: crw with N = 8 in 32x16', proc.stdout)
        self.assertTrue(os.path.isfile(out) and os.path.isfile(os.path.join(os.path.dirname(out), 'recommend.png')))
        with open(out) as f:
            self.assertIn('Recommended: crw', f.read())

    def test_2_model_fit_recovers_a_b_c(self):
        a, b, c = 3.0, 0.9, -1.0 / 2000
        sizes = [2 ** k for k in range(15)]
        noise = [1.0 + 0.01 * math.sin(7 * k) for k in range(len(sizes))]  # +-1 %, fixed
        f = model.fit([(n, a * n ** b * math.exp(c * n) * z, 10) for n, z in zip(sizes, noise)])
        self.assertAlmostEqual(f.a / a, 1.0, delta=0.05)
        self.assertAlmostEqual(f.b, b, delta=0.02)
        self.assertAlmostEqual(f.c / c, 1.0, delta=0.05)
        self.assertGreater(f.r2, 0.999)
        self.assertAlmostEqual(f.optimum(), 1800, delta=100)
        exact = model.fit([(n, a * n ** b * math.exp(c * n), 1) for n in (16, 64, 256, 1024)])
        self.assertAlmostEqual(exact.b, b, places=6)
        self.assertAlmostEqual(exact.optimum(), 1800, delta=1e-3)

    def test_3_fitted_sizes_and_the_optimum(self):
        a, b, c = 3.0, 0.9, -1.0 / 2000
        groups = {('crw', n): a * n ** b * math.exp(c * n) for n in (16, 64, 256, 1024)}
        folder = tables(os.path.join(self.tmp, 'ideal_64x32'), '64x32', groups, {}, {}, plan=False)
        proc, _ = self.run_recommend('arena: 64x32\nrobots: 4096\nweights: {performance: 1}\n', folder, output=False)
        self.assertEqual(proc.returncode, 0, proc.stderr + proc.stdout)
        self.assertIn('N* = -b/c = 1800', proc.stdout)
        self.assertIn('Recommended: crw with N = 1800', proc.stdout)
        self.assertIn('fitted beyond N=1024', proc.stdout)
        # The folder holds tables and no record: a sweep of its own, of the sizes missing, at the library's T.
        self.assertIn('rosrun swarm_forage sweep $(rospack find swarm_forage)/config/experiments/ideal_64x32.yaml '
                      '--sizes 2048,4096 --controllers crw --runs 10 --ticks 2000\n', proc.stdout)
        self.assertIn('- crw: P measured in 64x32 up to N = 1024; the target allows 4096 robots: N = 2048,4096 not '
                      'measured (the fit stands in up to N = 4096: two doublings):', proc.stdout)

    def test_4_names_what_is_missing_with_the_sweep_command(self):
        proc, _ = self.run_recommend(TARGET % (32, 'step_up', 0.8), output=False)
        self.assertEqual(proc.returncode, 0, proc.stderr + proc.stdout)
        # Per controller; one command for both, since it goes into the sweep's folder (its plan lists both).
        self.assertIn('- crw: P measured in 32x16 up to N = 8; the target allows 32 robots: N = 16,32 not measured '
                      '(no fit of P(N) stands in: it needs 3 sizes); dpo: P measured in 32x16 up to N = 8;',
                      proc.stdout)
        self.assertIn('rosrun swarm_forage sweep $(rospack find swarm_forage)/config/experiments/ideal_32x16.yaml --sizes 4,8,16,32 '
                      '--controllers crw,dpo --runs 2 --ticks 1500 --out ' + self.ideal, proc.stdout)
        self.assertIn('no sweep of 32x16 under step_up beta 0.8', proc.stdout)
        self.assertIn('- {waveform: step_up, beta: 0.8, alpha: -1}', proc.stdout)
        self.assertIn('rosrun swarm_forage sweep time_varying_32x16_step_up.yaml --sizes 4,8', proc.stdout)

    def test_5_bad_input_is_named_and_writes_nothing(self):
        base = TARGET % (8, 'step_down', 0.4)
        cases = [(base + 'colour: red\n', 2, "unknown key 'colour'; valid keys: name, description, arena"),
                 (base.replace('reactivity: 1', 'reactivity: -1'), 2, 'weights.reactivity is negative'),
                 (base.replace('2, scalability: 1, reactivity: 1, adaptability: 1', '0'), 2, 'weights are all zero'),
                 (base.replace('arena: 32x16', 'arena: 5x5'), 2, "arena '5x5' is not in config/arenas; valid: "),
                 (base.replace('arena: 32x16', 'arena: 96x48'), 1,
                  'no sweep of the library covers arena 96x48 (it covers 32x16)'),
                 (base.replace('arena: 32x16', 'arena: 96x48'), 1, 'sweep $(rospack find swarm_forage)/config/experiments/ideal_96x48.yaml'),
                 (base + 'noise: 0.015\n', 1, 'noise and population need robustness tables and no sweep of the '
                  'library has any; measure them with:\n  rosrun swarm_forage sweep '
                  '$(rospack find swarm_forage)/config/experiments/robustness_saa_32x16.yaml')]
        for text, code, message in cases:
            proc, out = self.run_recommend(text)
            self.assertEqual(proc.returncode, code, message + '\n' + proc.stderr + proc.stdout)
            self.assertIn(message, proc.stderr)
            self.assertFalse(os.path.exists(out), message)
            self.assertFalse(os.path.exists(os.path.dirname(out)), message)

    def test_6_incomplete_library_is_named(self):
        unfinished = os.path.join(self.tmp, 'unfinished')
        os.makedirs(os.path.join(unfinished, 'runs'))
        lacking = tables(os.path.join(self.tmp, 'lacking'), '32x16', P, E, Z, RA)
        os.remove(os.path.join(lacking, 'runs', 'dpo_n8_null_seed2_h.bag'))
        for folder, message in ((unfinished, 'no tables/series.csv (the sweep did not finish)'),
                                (lacking, '1 of 16 planned runs have no record (e.g. dpo_n8_null_seed2_h)')):
            proc, out = self.run_recommend(TARGET % (8, 'step_down', 0.4), folder)
            self.assertEqual(proc.returncode, 1, proc.stderr + proc.stdout)
            self.assertIn('incomplete sweeps in the library', proc.stderr)
            self.assertIn('%s: %s' % (folder, message), proc.stderr)
            self.assertFalse(os.path.exists(out))

    def test_7_a_controller_without_a_size_within_robots_is_listed_never_dropped(self):
        # CRW measured only above the robots available (16, 32 > 8), DPO at 4 and 8: CRW is no candidate, and
        # "what is missing" names it with the sweep that would measure it, per controller.
        groups = {('crw', 16): 50, ('crw', 32): 60, ('dpo', 4): 30, ('dpo', 8): 36}
        folder = tables(os.path.join(self.tmp, 'library_a'), '32x16', groups, {('crw', 32): 0.5, ('dpo', 8): 1.5},
                        {('crw', 32): 0.4, ('dpo', 8): 0.6}, plan=False)
        proc, _ = self.run_recommend('arena: 32x16\nrobots: 8\nweights: {performance: 1}\n', folder, output=False)
        self.assertEqual(proc.returncode, 0, proc.stderr + proc.stdout)
        self.assertIn('Recommended: dpo with N = 8', proc.stdout)
        self.assertIn("- crw: no size measured within the target's 8 robots in 32x16 (measured: N = 16,32), so it "
                      "is no candidate; N = 2,4,8 not measured:\n  rosrun swarm_forage sweep $(rospack find "
                      "swarm_forage)/config/experiments/ideal_32x16.yaml --sizes 2,4,8 --controllers crw --runs 10 "
                      "--ticks 2000\n", proc.stdout)
        # A folder without records (a copy of tables) is never written into: no --out, only the sizes asked.
        self.assertNotIn('--out', proc.stdout)
        # Nothing within robots at all: exit 1, each controller with its command.
        proc, _ = self.run_recommend('arena: 32x16\nrobots: 3\nweights: {performance: 1}\n', folder, output=False)
        self.assertEqual(proc.returncode, 1, proc.stderr + proc.stdout)
        self.assertIn('no candidate with N <= 3 robots in 32x16 (smallest measured: 4); measure one with:',
                      proc.stderr)
        self.assertIn("- crw: no size measured within the target's 3 robots", proc.stderr)
        self.assertIn("dpo: no size measured within the target's 3 robots in 32x16 (measured: N = 4,8)", proc.stderr)

    def test_8_a_study_folder_is_read_as_its_sweeps(self):
        study = os.path.join(self.tmp, 'study')
        tables(os.path.join(study, 'one'), '32x16', {('crw', 4): 20, ('crw', 8): 44}, {('crw', 8): 0.5},
               {('crw', 8): 0.4}, plan=False)
        tables(os.path.join(study, 'two'), '32x16', {('dpo', 4): 30, ('dpo', 8): 36}, {('dpo', 8): 1.5},
               {('dpo', 8): 0.6}, plan=False)
        proc, _ = self.run_recommend('arena: 32x16\nrobots: 8\nweights: {performance: 1}\n', study, output=False)
        self.assertEqual(proc.returncode, 0, proc.stderr + proc.stdout)
        self.assertIn('Library: study/one, study/two', proc.stdout)  # relative to the working folder, as typed
        self.assertIn('Recommended: crw with N = 8', proc.stdout)
        empty = os.path.join(self.tmp, 'empty_study')
        os.makedirs(os.path.join(empty, 'figures'))
        proc, _ = self.run_recommend(TARGET % (8, 'step_down', 0.4), empty, output=False)
        self.assertEqual(proc.returncode, 1, proc.stderr + proc.stdout)
        self.assertIn('%s: no tables/series.csv (the sweep did not finish); nor is it a study folder' % empty,
                      proc.stderr)

    def test_9_the_committed_study_as_a_fresh_clone_has_it(self):
        # The real script on the real committed folders, from the package's folder, writing only into the test's
        # folder: it needs no run, names a controller, and the committed answer is what it prints today.
        package = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
        target = os.path.join('config', 'targets', 'paper_section5.yaml')
        figure = os.path.join(self.tmp, 'committed.png')

        def recommend(target_path, *folders):
            return subprocess.run(RECOMMEND + [target_path] + list(folders) + ['--figure', figure],
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=package, timeout=120)
        proc = recommend(target, os.path.join('docs', 'paper_96'))
        self.assertEqual(proc.returncode, 0, proc.stderr + proc.stdout)
        self.assertRegex(proc.stdout, r'\nRecommended: (crw|dpo|gp_dpo) with N = \d+ in 96x48 ')
        self.assertIn('Library: docs/paper_96/ideal_96x48', proc.stdout)
        with open(os.path.join(package, 'docs', 'paper_96', 'recommend.txt')) as f:
            committed = f.read()
        library = next(line for line in committed.splitlines() if line.startswith('Library: '))
        proc = recommend(target, *library[len('Library: '):].split(', '))
        self.assertEqual(proc.returncode, 0, proc.stderr + proc.stdout)
        strip = lambda text: [x for x in text.splitlines() if not x.startswith('Figure: ')]  # noqa: E731
        self.assertEqual(strip(proc.stdout), strip(committed), 'docs/paper_96/recommend.txt is not what `recommend` '
                         'prints on its library: remake it (paper --publish, docs/study.md)')
        # 96x48 with 6,000 robots: every controller of the arm is ranked or listed as missing with its sweep.
        path = write(self.tmp, 'target_6000.yaml', 'arena: 96x48\nrobots: 6000\nweights: {performance: 1}\n')
        proc = recommend(path, os.path.join('docs', 'paper_96'))
        self.assertIn(proc.returncode, (0, 1), proc.stderr + proc.stdout)
        text = proc.stdout + proc.stderr
        controllers = set()
        for series in glob.glob(os.path.join(package, 'docs', 'paper_96', '*', 'tables', 'series.csv')):
            with open(series) as f:
                controllers |= {r['controller'] for r in csv.DictReader(f)
                                if r['arena'] == '96x48' and r['waveform'] == 'null'}
        self.assertTrue(controllers)
        ranked = {line.split()[1] for line in proc.stdout.splitlines() if line.split()[:1] and line.split()[0].isdigit()
                  and line.split()[1] in controllers}
        for c in controllers - ranked:
            self.assertRegex(text, r"(- |; )%s: no size measured within the target's 6000 robots in 96x48" % c)

    def test_10_paper_publish_writes_a_library_recommend_reads(self):
        # The arm as `paper` leaves it (a sweep folder of the committed tables), reported again and published
        # into a folder of the test's: every table in DEST/<sweep>/tables, verdicts naming DEST's folders, and
        # the report's recommend section remade on DEST, as `recommend TARGET DEST` answers.
        package = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
        out, dest = os.path.join(self.tmp, 'results', 'paper_96'), os.path.join(self.tmp, 'docs', 'paper_96')
        shutil.copytree(os.path.join(package, 'docs', 'paper_96', 'ideal_96x48', 'tables'),
                        os.path.join(out, 'ideal_96x48', 'tables'))
        proc = subprocess.run(['rosrun', 'swarm_forage', 'paper', '--arm-96', '--report-only', '--out', out,
                               '--publish', dest], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                              cwd=self.tmp, timeout=600)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        self.assertEqual(sorted(os.listdir(os.path.join(dest, 'ideal_96x48', 'tables'))),
                         sorted(os.listdir(os.path.join(out, 'ideal_96x48', 'tables'))))
        self.assertFalse(os.path.exists(os.path.join(dest, 'ideal_96x48', 'runs')))
        with open(os.path.join(dest, 'verdicts.json')) as f:
            groups = [g[0] for c in json.load(f) for g in c['groups']]
        self.assertTrue(groups)
        self.assertEqual(set(groups), {os.path.join(dest, 'ideal_96x48')})
        with open(os.path.join(dest, 'report.md')) as f:
            report = f.read()
        self.assertEqual(report.count("## `recommend` on the paper's target"), 1)
        self.assertIn('`rosrun swarm_forage recommend config/targets/paper_section5.yaml %s`' % dest, report)
        with open(os.path.join(dest, 'recommend.txt')) as f:
            answer = f.read()
        self.assertIn('Library: %s\n' % os.path.join(dest, 'ideal_96x48'), answer)
        self.assertIn(answer.split('\nFigure: ')[0], report)
        self.assertTrue(os.path.isfile(os.path.join(dest, 'recommend.png')))
        proc = subprocess.run(RECOMMEND + [os.path.join(package, 'config', 'targets', 'paper_section5.yaml'), dest,
                                           '--figure', os.path.join(self.tmp, 'published.png')],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=package, timeout=120)
        self.assertEqual(proc.returncode, 0, proc.stderr + proc.stdout)
        self.assertEqual(proc.stdout.split('\nFigure: ')[0], answer.split('\nFigure: ')[0])


if __name__ == '__main__':
    unittest.main()
