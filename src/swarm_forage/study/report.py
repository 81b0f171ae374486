"""The paper's claims against measured sweeps, claim by claim, as markdown:

    paper_report.py --ideal DIR [DIR ...] [--time-varying DIR] [--robustness DIR ...] [--figures FIGDIR] --output REPORT.md

Each claim is a quantity computed from the sweeps' bootstrap tables (swarm_forage.study.paper_claims) with a 95 %
interval over seeds, compared with a stated threshold: agrees, disagrees, undecided (the interval straddles the
threshold; with the seeds a normal approximation says would decide it), or not measured (what is missing).
--json writes the verdicts for `paper --decide`.
--robustness adds the section "Beyond the paper: robustness" (swarm_forage.robustness.report): which
controller degrades least under noise and under population dynamics, at each N.
The model the runs used (swarm_forage or fordyca_2019, and any quirks added) is read from each record's
world/run_info (its world and controller constants: the identity words quirks=...), never from a flag.
A sweep whose planned records are not all there (it has not finished) is refused (exit 1, saying how many
are missing) unless --partial is given; the report then says at its top that it is partial.
"""
import argparse
import glob
import math
import os
import sys

from swarm_forage.bags import runs
from swarm_forage.experiment import kinds, models
from swarm_forage.robustness import report as robustness_report
from swarm_forage.study import bootstrap, claims, intervals, paper_claims
from swarm_forage.sweep import records

PAPER = claims.PAPER  # the controllers the paper's claims are about


label = kinds.display_name


def finals(folder):
    """(arena, controller, N) -> intervals.Interval of the ideal groups' mean final P: the 95 % interval of
    the bootstrap over seeds, as every claim's."""
    try:
        draws = bootstrap.read(folder, key=bootstrap.by_identity)
    except bootstrap.BootstrapMissing:
        draws = None
    return {k: intervals.point_interval(draws, r['identity'], 'P', float(r['P_mean']), int(r['runs']), True)
            for k, r in runs.final_samples(runs.sweep_table(folder, 'series')).items()}


def fmt(v, digits=3):
    return '—' if v is None or (isinstance(v, float) and math.isnan(v)) else '%.*f' % (digits, v)


def claim_lines(c):
    """A claim's section: the paper's words, the criterion, the measured quantity with its interval and seeds,
    each threshold's sensitivity, and the verdict."""
    lines = ['### (%s) %s' % (c.tag, c.paper), '', '- **Criterion:** ' + c.criterion]
    if c.verdict == 'not measured':
        return lines + ['- **Measured:** ' + (c.missing or 'nothing'), '- **Verdict:** **not measured**', '']
    lines.append('- **Measured:** %s = %s, 95 %% bootstrap interval [%s, %s] (%d of %d draws defined); seeds per '
                 'group: %s. %s' % (c.quantity or 'the quantity', fmt(c.estimate), fmt(c.low), fmt(c.high),
                                    c.defined, c.draws, c.seeds_text(), c.evidence))
    for s in c.sensitivity:
        lines.append('- **Threshold:** ' + s)
    verdict = c.verdict
    if c.verdict == 'undecided':
        verdict += ' — ' + c.seeds_words()
    return lines + ['- **Verdict:** **%s**' % verdict, '']


def verdict_table(claim_list):
    out = ['| claim | criterion | measured | 95 % interval | seeds | verdict |', '|---|---|---|---|---|---|']
    for c in claim_list:
        out.append('| (%s) | %s %s %s | %s | %s | %s | %s%s |' % (
            c.tag, c.quantity or '—', c.op or '', '' if c.threshold is None else '%g' % c.threshold,
            fmt(c.estimate), '—' if math.isnan(c.low) else '[%s, %s]' % (fmt(c.low), fmt(c.high)), c.seeds_text(),
            c.verdict, c.seeds_short()))
    return out + ['']


def record_quirks(path):
    """The quirks of the record at `path` (its world/run_info's world and controller constants), or None when
    it holds no run_info."""
    import rosbag
    with rosbag.Bag(path) as bag:
        info = next((m for _, m, _ in bag.read_messages(topics=['/world/run_info'])), None)
    if info is None:
        return None
    out = set()
    for word in (info.world_constants + ' ' + info.controller_constants).split():
        if word.startswith('quirks='):
            out.update(q for q in word[len('quirks='):].split(',') if q)
    return out


def model_of(quirks):
    """A set of quirks as the setting that gives it (models.model_name: 'swarm_forage' or 'fordyca_2019', with
    '+QUIRK' for each added), whichever model is the default."""
    return models.model_name(quirks)


def models_used(folders):
    """(lines for the report, {model: records}) of every planned record of the sweep folders."""
    used, unreadable = {}, 0
    for folder in folders:
        paths = sorted(glob.glob(os.path.join(folder, 'plan', '*.bag'))) or \
            sorted(glob.glob(os.path.join(folder, 'runs', '*.bag')))
        for path in paths:
            try:
                quirks = record_quirks(path)
            except Exception:  # rosbag raises several kinds; the sweep has verified its records
                quirks = None
            if quirks is None:
                unreadable += 1
                continue
            used[model_of(quirks)] = used.get(model_of(quirks), 0) + 1
    if not used:
        return ['**Model:** not known (no record with a world/run_info in the sweeps).', ''], used
    total = sum(used.values())
    where = 'read from the world/run_info of the %d records of the sweeps%s' % (
        total, ' (%d without one)' % unreadable if unreadable else '')
    if len(used) == 1:
        model = next(iter(used))
        what = ' (FORDYCA 2019\'s quirks, docs/FIDELITY.md)' if model.startswith('fordyca_2019') else \
            ' (no quirk)' if model == 'swarm_forage' else ''
        what += ', the default' if model == models.models()['default'] else ''
        return ['**Model:** %s%s; %s.' % (model, what, where), ''], used
    return ['**Models: mixed**, %s: %s. The claims below pool them.' % (
        where, '; '.join('%s: %d records' % kv for kv in sorted(used.items()))), ''], used


def cell(interval):
    """'mean [low, high]', or the mean with why it has no interval."""
    if interval.drawn:
        return '%.1f [%.1f, %.1f]' % (interval.estimate, interval.lo, interval.hi)
    return '%.1f (%s)' % (interval.estimate, interval.note)


def every_controller(ideal):
    """Final P of every controller the ideal sweeps ran, the paper's and any other (a plugin's) alike."""
    p = {}
    for folder in ideal:
        p.update(finals(folder))
    order = list(kinds.controller_names())
    controllers = sorted({c for (_, c, _) in p}, key=lambda c: (order.index(c) if c in order else len(order), c))
    if not controllers:
        return []
    out = ['## Every controller measured', '', 'Final P of the ideal sweeps: mean [95 % bootstrap interval over '
           'seeds].', '',
           '| arena | N | ' + ' | '.join(label(c) for c in controllers) + ' |',
           '|---|---|' + '---|' * len(controllers)]
    for arena, n in sorted({(a, n) for (a, _, n) in p}):
        cells = [cell(p[(arena, c, n)]) if (arena, c, n) in p else '—' for c in controllers]
        out.append('| %s | %d | %s |' % (arena, n, ' | '.join(cells)))
    return out + ['']


def parse(argv):
    ap = argparse.ArgumentParser(prog='paper_report.py', description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter,
                                 epilog='example:\n  paper_report.py --ideal results/paper_quick/ideal_32x16 '
                                        '--output report.md   # what `paper` calls')
    ap.add_argument('--ideal', nargs='+', required=True, help='ideal-condition sweep folders')
    ap.add_argument('--time-varying', help='the time-varying sweep folder')
    ap.add_argument('--robustness', nargs='+', default=[], help='robustness sweep folders (noise, population '
                    'dynamics): the section "Beyond the paper: robustness"')
    ap.add_argument('--figures', help='folder of plot_sweep.py figures to show (relative links)')
    ap.add_argument('--output', required=True, help='the markdown file to write')
    ap.add_argument('--title', default='swarm_forage: the paper\'s claims, measured', help='(default: %(default)s)')
    ap.add_argument('--note', default='', help='a line on how the data was made (seeds, sizes, time)')
    ap.add_argument('--claims', help='comma-separated claims to report (e.g. c,d for the 96×48 arm; default: all)')
    ap.add_argument('--json', help='also write the verdicts as JSON (what `paper --decide` reads)')
    ap.add_argument('--partial', action='store_true', help='report on sweeps that have not finished (the report '
                    'says so); without it such a sweep is refused')
    return ap.parse_args(argv)


def sweep_folders(a):
    """Every sweep folder the report reads: ideal, time-varying, robustness."""
    return a.ideal + ([a.time_varying] if a.time_varying else []) + a.robustness


def chosen_claims(a):
    """(the claims --claims names, or all; the sweeps without a bootstrap)."""
    claim_list, no_bootstrap = paper_claims.evaluate(a.ideal, a.time_varying, label)
    if a.claims:
        wanted = a.claims.split(',')
        claim_list = [c for c in claim_list if c.tag in wanted or c.tag.rstrip('1234') in wanted]
    return claim_list, no_bootstrap


def method_lines(claim_list, no_bootstrap):
    """How a claim is decided: the bootstrap, the verdicts' meaning and the thresholds."""
    return ['Each claim is a quantity computed from the sweeps\' tables with a 95 %% bootstrap interval over seeds '
            '(%s draws; each group\'s seeds resampled, every metric recomputed per draw: docs/metrics.md, '
            'Bootstrap). *agrees*: the whole interval is on the claim\'s side of its threshold; *disagrees*: wholly '
            'on the other; *undecided*: it straddles the threshold, or a group has fewer than %d seeds. '
            'Thresholds: "Z below 0.5" is Z < %.2f; "about as well" is within %d %%; "better at small N" is at '
            '%.0f %% or more of the sizes N ≤ %d; each is listed under its claim with where the verdict turns.%s'
            % (next((str(c.draws) for c in claim_list if c.draws), 'no'), claims.MIN_SEEDS, claims.Z_BELOW,
               round(100 * claims.WITHIN), 100 * claims.SHARE, claims.SMALL_N,
               ' No bootstrap in %s: rerun `sweep` there.' % ', '.join(no_bootstrap) if no_bootstrap else ''), '']


def figure_lines(figures, output):
    """The section of every figure under `figures`, linked relative to the report at `output`."""
    base = os.path.dirname(os.path.abspath(output))
    out = ['## Figures', '']
    for root, _, files in sorted(os.walk(figures)):
        for f in sorted(files):
            if f.endswith('.png'):
                rel = os.path.relpath(os.path.join(root, f), base)
                out += ['![%s](%s)' % (f[:-4].replace('_', ' '), rel), '']
    return out


def report_lines(a, lacking, claim_list, no_bootstrap):
    """(the report's lines, {model: records}, the robustness section's verdicts)."""
    out = ['# ' + a.title, '']
    if lacking:
        out += ['**Partial:** these sweeps have not finished, and the claims below are measured on the records so '
                'far: %s.' % '; '.join(lacking), '']
    model_lines, used = models_used(sweep_folders(a))
    out += model_lines
    if a.note:
        out += [a.note, '']
    out += method_lines(claim_list, no_bootstrap)
    out += verdict_table(claim_list)
    for c in claim_list:
        out += claim_lines(c)
    out += every_controller(a.ideal)
    robustness, beyond = robustness_report.section(a.robustness, label) if a.robustness else ([], [])
    out += robustness
    if a.figures:
        out += figure_lines(a.figures, a.output)
    return out, used, beyond


def print_verdicts(claim_list, used, beyond, json_path):
    """What `paper` shows of the report: the model, each claim's verdict and the robustness verdicts; the
    verdicts as JSON at `json_path` too, if given."""
    print('model: %s' % ('; '.join('%s (%d records)' % kv for kv in sorted(used.items())) or 'not known'))
    for c in claim_list:
        print('(%s) %s%s' % (c.tag, c.verdict, '' if math.isnan(c.estimate) else ': %s = %.3f [%.3f, %.3f], %s seeds'
                                % (c.quantity, c.estimate, c.low, c.high, c.seeds_text())))
    if json_path:
        import json
        with open(json_path, 'w') as f:
            json.dump([c.as_json() for c in claim_list], f, indent=1)
    for what, verdict in beyond:
        print('%s: %s' % (what, verdict))


def main(argv=None):
    a = parse(argv)
    lacking = records.incomplete(sweep_folders(a))
    if lacking and not a.partial:
        print('paper_report: the sweeps have not finished: %s; run them to their end, or give --partial to report '
              'on what there is' % '; '.join(lacking), file=sys.stderr)
        return 1
    claim_list, no_bootstrap = chosen_claims(a)
    out, used, beyond = report_lines(a, lacking, claim_list, no_bootstrap)
    with open(a.output, 'w') as f:
        f.write('\n'.join(out) + '\n')
    print(a.output)
    print_verdicts(claim_list, used, beyond, a.json)
    return 0


if __name__ == '__main__':  # paper runs it so, a process of its own
    sys.exit(main())
