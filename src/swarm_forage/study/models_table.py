"""The README's results table: each of the paper's claims as the committed reports decided it, under FORDYCA's
model and under the corrected one, side by side (read from each study's verdicts.json, `paper_report.py --json`).

rosrun swarm_forage models_table --default docs/paper_quick docs/paper_96 --corrected docs/paper_quick_swarm_forage
docs/paper_96_swarm_forage [--check README.md]
"""
import argparse
import json
import os
import sys

# What the paper says, and the report's criterion (swarm_forage.study.paper_claims), in a few words each.
CLAIMS = [
    ('a1', '32×16: CRW the most scalable', 'm = min e of DPO, GP-DPO − e of CRW > 0'),
    ('a2', '32×16: DPO, GP-DPO better at N ≤ 64', 'share of sizes s ≥ 2/3'),
    ('b', '64×32: N of max P ≈ N of first Z < 0.5', 'steps apart k ≤ 1'),
    ('c', 'CRW the best at the largest N', 'r = P(CRW)/best other − 1 > 0'),
    ('d', '96×48: DPO 2,048 ≈ CRW 8,192', 'q = \\|ΔP\\|/P(CRW) ≤ 0.15'),
    ('e1', 'step_down: GP-DPO the most reactive', 'g > 0 (each (N, β) weighs the same)'),
    ('e2', 'step_down: GP-DPO the most adaptive', 'g > 0'),
    ('e3', 'R falls as β grows', 'largest mean Spearman ρ < 0'),
    ('e4', 'A falls as β grows', 'largest mean Spearman ρ < 0'),
]
BEGIN = '<!-- models_table: begin -->'
END = '<!-- models_table: end -->'


def verdicts(studies):
    """{claim: (verdict dict, study)}: a later study that measured a claim replaces an earlier one's (the 96×48 arm
    decides (c) at the paper's largest N and (d), the reduced study the rest)."""
    out = {}
    for study in studies:
        path = os.path.join(study, 'verdicts.json')
        if not os.path.exists(path):
            raise SystemExit('models_table: %s has no verdicts.json (paper_report.py --json writes it)' % study)
        with open(path) as f:
            for v in json.load(f):
                if v['verdict'] != 'not measured':
                    out[v['claim']] = (v, study)
    return out


def number(x):
    return ('%.3f' % x).replace('-', '−')


def cell(entry):
    if entry is None:
        return 'not measured'
    v, study = entry
    seeds = v['seeds']
    text = '%s %s %s [%s, %s], %s seeds' % (
        '**%s**:' % v['verdict'] if v['verdict'] == 'agrees' else '%s:' % v['verdict'], v['quantity'],
        number(v['margin']), number(v['low']), number(v['high']),
        '–'.join(str(s) for s in ([seeds[0], seeds[-1]] if len(seeds) > 1 else seeds)))
    if v['verdict'] == 'undecided' and v.get('seeds_needed'):
        # At or below the seeds already run, the normal approximation is no guide (skewed draws), as the
        # report says.
        text += (' (≈ %d would decide)' % v['seeds_needed'] if v['seeds_needed'] > max(seeds)
                 else ' (the normal approximation is no guide: skewed draws)')
    return text + ' ([%s](%s/report.md))' % (os.path.basename(study), study)


def table(default, corrected):
    lines = ['| claim | the paper | criterion | FORDYCA\'s model (default) | corrected model |', '|---|---|---|---|---|']
    for tag, paper, criterion in CLAIMS:
        lines.append('| (%s) | %s | %s | %s | %s |' % (tag, paper, criterion, cell(default.get(tag)),
                                                       cell(corrected.get(tag))))
    return lines


def main(argv=None):
    ap = argparse.ArgumentParser(prog='models_table', description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--default', nargs='+', required=True, metavar='STUDY', help='studies under fordyca_2019')
    ap.add_argument('--corrected', nargs='+', required=True, metavar='STUDY', help='studies under swarm_forage')
    ap.add_argument('--check', metavar='FILE', help='exit 1 unless FILE holds this table between %s and %s' % (
        BEGIN, END))
    ap.add_argument('--write', metavar='FILE', help='replace the table between the markers in FILE')
    a = ap.parse_args(argv)
    rows = table(verdicts(a.default), verdicts(a.corrected))
    target = a.check or a.write
    if not target:
        print('\n'.join(rows))
        return 0
    with open(target) as f:
        text = f.read()
    if BEGIN not in text or END not in text:
        sys.stderr.write('models_table: %s has no %s ... %s markers\n' % (target, BEGIN, END))
        return 1
    head, rest = text.split(BEGIN, 1)
    old, tail = rest.split(END, 1)
    new = '\n' + '\n'.join(rows) + '\n'
    if a.check:
        if old != new:
            sys.stderr.write('models_table: the table in %s is not what the committed verdicts say; remake it with '
                             '`rosrun swarm_forage models_table ... --write %s`\n' % (target, target))
            return 1
        print('models_table: %s is current' % target)
        return 0
    with open(target, 'w') as f:
        f.write(head + BEGIN + new + END + tail)
    print(target)
    return 0
