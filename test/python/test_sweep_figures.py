#!/usr/bin/env python3
"""Uncertainty in every figure: plot_sweep.py on a synthetic sweep folder (its five tables and a
hand-made bootstrap.csv) draws e, Z, R, A and final P with their 95 % bootstrap percentile intervals, P(N, t)
bands never below zero, says where a point has no interval (1 seed, no bootstrap.csv), labels e from the
tables' N1/N2 and titles a time-varying sweep's figures of its ideal groups as such."""
import os
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.join(os.path.dirname(os.path.realpath(__file__)), '..', 'helpers'))
from tmp_files import removed_at_exit

HERE = os.path.dirname(os.path.abspath(__file__))
SCRIPTS = os.path.join(HERE, '..', '..', 'scripts')

from swarm_forage.figures import sweep as plot_sweep  # noqa: E402
from swarm_forage.study import bootstrap, intervals  # noqa: E402

ARENA = '32x16'
SIZES = (16, 64, 256)  # N1 = N/4: e(N/4, N)
SEEDS = {('crw', 16): 2, ('crw', 64): 2, ('crw', 256): 2, ('dpo', 16): 2, ('dpo', 64): 2, ('dpo', 256): 1}
CHANGES = (('step_down', 0.1), ('step_down', 0.4))  # time-varying groups at N = 16 and 64
# Bootstrap draws 1..5 are the measured value times these: percentile interval (2.5 %, 97.5 %) of 5 sorted
# values, linearly interpolated at positions 0.1 and 3.9, is value * (0.525, 1.475).
FACTORS = (1.5, 0.5, 1.25, 0.75, 1.0)
LOW, HIGH = 0.525, 1.475
HEAD = 'controller,arena,waveform,beta,environment,'
TAIL = ',sample_interval,identity'


def p_final(c, n):
    return {'crw': 2.0, 'dpo': 3.0}[c] * n


def e_value(c, n):
    return {'crw': 1.0, 'dpo': 2.0}[c] + n / 256.0


def z_value(c, n):
    return {'crw': 0.6, 'dpo': 0.7}[c] - n / 1024.0


def ra_value(metric, c, n, beta):
    return {'R': 100.0, 'A': 20.0}[metric] * (1 + n / 64.0) * (1.5 - beta) * {'crw': 1.0, 'dpo': 1.2}[c]


def groups():
    """(controller, N, waveform, beta, seeds) of every group."""
    for (c, n), seeds in sorted(SEEDS.items()):
        yield c, n, 'null', 0.0, seeds
        if n < 256:
            for w, beta in CHANGES:
                yield c, n, w, beta, 2


def write_table(folder, name, header, rows):
    with open(os.path.join(folder, 'tables', name + '.csv'), 'w') as f:
        f.write(header + '\n')
        for r in rows:
            f.write(','.join(str(v) for v in r) + '\n')


def make_sweep(folder, with_bootstrap=True):
    """A sweep folder with the tables run_tables writes (headers of src/core/metrics/metric_tables.cpp)."""
    os.makedirs(os.path.join(folder, 'tables'))
    series, scal, selforg, flex, boot = [], [], [], [], []
    for c, n, w, beta, seeds in groups():
        env = '"%s"' % ('ideal' if w == 'null' else '%s beta=%g' % (w, beta))
        common = [c, ARENA, w, beta, env]
        ident = '%s_%d_%s_%g' % (c, n, w, beta)
        final = p_final(c, n) * (1.0 if w == 'null' else 0.8)
        for k in range(5):  # a spread so big (2 seeds: Student t 12.7) that mean - ci95 < 0
            mean = final * (k + 1) / 5.0
            series.append([c, ARENA, n, w, beta, -1, seeds, k, 500 * (k + 1) - 1, mean, 1.5 * mean if seeds > 1
                           else 'nan', 0, 0, 0, 0, 500, ident])
        values = {'P': final, 'e': '', 'Z': '', 'R': '', 'A': ''}
        if w == 'null':
            if n > SIZES[0]:
                values['e'], values['Z'] = e_value(c, n), z_value(c, n)
                scal.append(common + [n // 4, n, 2, seeds, 0.5, values['e'], 1, '"ok"', 500, ident])
                selforg.append(common + [n // 4, n, seeds, 0.1, 1.0, values['Z'], 1, '"ok"', 500, ident])
        else:
            values['R'], values['A'] = ra_value('R', c, n, beta), ra_value('A', c, n, beta)
            flex.append(common + [n, seeds, values['R'], values['A'], 1, '"ok"', 500, ident])
        for d, f in enumerate((1.0,) + FACTORS):
            boot.append([d] + common[:4] + [env, n, seeds] +
                        [v if v == '' else v * f for v in (values[m] for m in bootstrap.METRICS)] + [500, ident])
    write_table(folder, 'series', 'controller,arena,swarm_size,waveform,beta,alpha,runs,sample,tick_end,P_mean,'
                'P_ci95,p_mean,p_ci95,n_ca_mean,n_ca_ci95' + TAIL, series)
    write_table(folder, 'scalability', HEAD + 'N1,N2,N_used,runs,phi,e,valid,status' + TAIL, scal)
    write_table(folder, 'self_organization', HEAD + 'm_prev,m_i,runs,theta_Z,Z_sum,Z_mean,valid,status' + TAIL,
                selforg)
    write_table(folder, 'flexibility', HEAD + 'N,runs,R,A,valid,status' + TAIL, flex)
    if with_bootstrap:
        write_table(folder, 'bootstrap', 'draw,controller,arena,waveform,beta,environment,N,runs,P,e,Z,R,A' + TAIL,
                    boot)
    return folder


def bars(fig):
    """The (low, high) of every error bar drawn in the figure's axes."""
    out = []
    for ax in fig.axes:
        for coll in ax.collections:
            if type(coll).__name__ == 'LineCollection':
                out += [(min(s[0][1], s[1][1]), max(s[0][1], s[1][1])) for s in coll.get_segments()]
    return out


def texts(fig):
    found = [t.get_text() for t in fig.texts]
    for ax in fig.axes:
        found += [ax.title.get_text(), ax.yaxis.label.get_text()] + [t.get_text() for t in ax.texts]
        if ax.get_legend():
            found.append(ax.get_legend().get_title().get_text())
    for leg in fig.legends:
        found.append(leg.get_title().get_text())
    return '\n'.join(found)


class SweepFigures(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = removed_at_exit(tempfile.mkdtemp(prefix='swarm_forage_sweep_figures_'))

    def plot(self, folder):
        """plot_sweep.py's main in this process: {file name: the figure as drawn} (and the PNGs written)."""
        drawn, original = {}, plot_sweep.save

        def save(fig, out, name):
            drawn[name] = fig
            fig.canvas.draw()
            return original(fig, out, name)

        plot_sweep.save = save
        try:
            self.assertEqual(plot_sweep.main([folder, '--output', os.path.join(self.tmp, 'figures')]), 0)
        finally:
            plot_sweep.save = original
        return drawn

    def test_1_script_writes_every_figure(self):
        folder = make_sweep(os.path.join(self.tmp, 'tv'))
        out = os.path.join(self.tmp, 'script_figures')
        proc = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'plot_sweep.py'), folder, '--output', out],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
        self.assertEqual(proc.returncode, 0, proc.stdout)
        for name in ('performance', 'final_performance', 'scalability', 'self_organization', 'flexibility'):
            path = os.path.join(out, 'tv', '%s_%s.png' % (name, ARENA))
            self.assertTrue(os.path.isfile(path) and os.path.getsize(path) > 1000, proc.stdout)

    def test_2_interval_function_gives_the_bootstrap_percentiles(self):
        folder = make_sweep(os.path.join(self.tmp, 'one'))
        draws = bootstrap.read(folder)
        for metric, c, n, value in (('e', 'crw', 64, e_value('crw', 64)), ('Z', 'dpo', 64, z_value('dpo', 64)),
                                    ('P', 'dpo', 64, p_final('dpo', 64))):
            iv = intervals.point_interval(draws, (ARENA, c, n, 'null', 0.0), metric, value, 2)
            self.assertTrue(iv.drawn, iv)
            self.assertAlmostEqual(iv.lo, LOW * value, places=9)
            self.assertAlmostEqual(iv.hi, HIGH * value, places=9)
        iv = intervals.point_interval(draws, (ARENA, 'crw', 16, 'step_down', 0.4), 'R',
                                            ra_value('R', 'crw', 16, 0.4), 2)
        self.assertAlmostEqual(iv.lo, LOW * ra_value('R', 'crw', 16, 0.4), places=9)
        one = intervals.point_interval(draws, (ARENA, 'dpo', 256, 'null', 0.0), 'e', 3.0, 1)
        self.assertFalse(one.drawn)
        self.assertEqual(one.note, 'no interval: 1 seed')
        none = intervals.point_interval(None, (ARENA, 'crw', 64, 'null', 0.0), 'e', 1.25, 2)
        self.assertEqual(none.note, intervals.NO_BOOTSTRAP)
        self.assertEqual(intervals.count_band(100.0, 1800.0, 2), (0.0, 1900.0))
        self.assertIsNone(intervals.count_band(100.0, float('nan'), 1))

    def test_3_figures_draw_those_intervals(self):
        drawn = self.plot(make_sweep(os.path.join(self.tmp, 'two')))
        name = lambda n: '%s_%s.png' % (n, ARENA)  # noqa: E731

        def expect(fig, values):
            got = sorted(bars(fig))
            want = sorted((LOW * v, HIGH * v) for v in values)
            self.assertEqual(len(got), len(want), (got, want))
            for (a, b), (c, d) in zip(got, want):
                self.assertAlmostEqual(a, c, places=6)
                self.assertAlmostEqual(b, d, places=6)

        # e and Z at N = 64 and 256 except DPO at 256 (1 seed: a hollow point and a note instead)
        two = [('crw', 64), ('crw', 256), ('dpo', 64)]
        expect(drawn[name('scalability')], [e_value(c, n) for c, n in two])
        expect(drawn[name('self_organization')], [z_value(c, n) for c, n in two])
        expect(drawn[name('final_performance')], [p_final(c, n) for c, n in sorted(SEEDS) if SEEDS[(c, n)] > 1])
        expect(drawn[name('flexibility')], [ra_value(m, c, n, b) for m in 'RA' for c in ('crw', 'dpo')
                                            for n in SIZES[:2] for _, b in CHANGES])
        for n in ('scalability', 'self_organization', 'final_performance'):
            words = texts(drawn[name(n)])
            self.assertIn('no interval: 1 seed', words, n)
            self.assertIn('DPO at N = 256', words, n)
            self.assertIn(intervals.CAPTION, words, n)
            self.assertIn('1\u20132 seeds per group', words, n)
        self.assertIn('2 seeds per group', texts(drawn[name('flexibility')]))

        # P(N, t) bands of a count never go below zero, and are drawn (clipped, not dropped)
        lows = [v[1] for ax in drawn[name('performance')].axes for coll in ax.collections
                for path in coll.get_paths() for v in path.vertices]
        self.assertTrue(lows, 'no bands drawn')
        self.assertGreaterEqual(min(lows), 0.0)
        self.assertEqual(min(lows), 0.0)
        self.assertIn('no interval: 1 seed', texts(drawn[name('performance')]))

        # e's label from N1/N2; the time-varying sweep's figures of ideal groups say so
        scal = drawn[name('scalability')]
        self.assertEqual(scal.axes[0].yaxis.label.get_text(), 'Karp-Flatt e(N/4, N)')
        for n in ('scalability', 'self_organization', 'final_performance'):
            self.assertIn('ideal groups of the time-varying sweep', drawn[name(n)].axes[0].title.get_text(), n)

        # flexibility: one legend outside the axes, long handles, a marker per N
        flex = drawn[name('flexibility')]
        self.assertTrue(all(ax.get_legend() is None for ax in flex.axes))
        self.assertEqual(len(flex.legends), 1)
        legend = flex.legends[0]
        self.assertGreaterEqual(legend.handlelength, 4)
        box, axes_right = legend.get_window_extent(), max(ax.get_window_extent().x1 for ax in flex.axes)
        self.assertGreaterEqual(box.x0, axes_right)
        markers = {t.get_text(): h.get_marker() for t, h in zip(legend.get_texts(), legend.legend_handles
                                                               if hasattr(legend, 'legend_handles')
                                                               else legend.legendHandles)}
        self.assertNotEqual(markers['CRW N=16'], markers['CRW N=64'])

    def test_4_no_bootstrap_says_so(self):
        drawn = self.plot(make_sweep(os.path.join(self.tmp, 'plain'), with_bootstrap=False))
        scal = drawn['scalability_%s.png' % ARENA]
        self.assertEqual(bars(scal), [])
        self.assertIn('no bootstrap.csv', texts(scal))
        # final P falls back to series.csv's Student t interval, clipped at 0
        final = drawn['final_performance_%s.png' % ARENA]
        self.assertIn(intervals.T_CAPTION, texts(final))
        self.assertTrue(bars(final))
        self.assertGreaterEqual(min(lo for lo, _ in bars(final)), 0.0)

    def test_5_e_label_follows_n1_n2(self):
        self.assertEqual(intervals.ratio_label([(8, 16), (16, 32)]), 'Karp-Flatt e(N/2, N)')
        self.assertEqual(intervals.ratio_label([(4, 16), (16, 64)]), 'Karp-Flatt e(N/4, N)')
        self.assertEqual(intervals.ratio_label([(8, 16), (16, 64)]), 'Karp-Flatt e(N1, N), N1 = N/2 or N/4')

    def test_6_an_unfinished_sweep_is_refused_unless_partial(self):
        folder = make_sweep(os.path.join(self.tmp, 'unfinished'))
        with open(os.path.join(folder, 'runs.tsv'), 'w') as f:  # the plan: three runs, one recorded
            f.write('a\tseed:=1\nb\tseed:=2\nc\tseed:=3\n')
        os.makedirs(os.path.join(folder, 'runs'))
        open(os.path.join(folder, 'runs', 'b.bag'), 'w').close()
        out = os.path.join(self.tmp, 'unfinished_figures')
        proc = subprocess.run([sys.executable, os.path.join(SCRIPTS, 'plot_sweep.py'), folder, '--output', out],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=300)
        self.assertEqual(proc.returncode, 1, proc.stdout)
        self.assertIn('%s: 2 of 3 planned records missing' % folder, proc.stdout)
        self.assertIn('--partial', proc.stdout)
        self.assertFalse(os.path.exists(out), 'figures of an unfinished sweep were drawn')
        # --partial draws them, each marked.
        marked, original = [], plot_sweep.plt.Figure.savefig

        def savefig(fig, *args, **kwargs):
            marked.append(any(t.get_text() == 'PARTIAL: 2 of 3 planned records missing' for t in fig.texts))
            return original(fig, *args, **kwargs)

        plot_sweep.plt.Figure.savefig = savefig
        try:
            self.assertEqual(plot_sweep.main([folder, '--output', out, '--partial']), 0)
        finally:
            plot_sweep.plt.Figure.savefig = original
        self.assertTrue(marked and all(marked), marked)


if __name__ == '__main__':
    unittest.main()
