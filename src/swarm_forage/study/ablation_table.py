"""The ablation table of FORDYCA 2019's quirks from its sweeps' tables (swarm_forage.study.ablation):

    ablation_table.py SWEEP_DIR [SWEEP_DIR ...] --output TABLE.md [--csv RUNS.csv]

One row per quirk set (swarm_forage, fordyca_2019, swarm_forage+QUIRK, fordyca_2019+QUIRK), two columns per arm
(sweep folder, controller and N): final P, mean [95 % bootstrap interval over seeds] (min-max), and the robots
stalled at T; per row claim (d) with its bootstrap interval and verdict, as the report decides it. --csv writes
one line per record (arm, row, seed, model version, quirks, identity, ticks, final P, stalled, code, record).
`paper --ablation` runs the sweeps and then this; a sweep whose planned records are not all there is refused
(exit 1) unless --partial is given, and the table then says so.
"""
import argparse
import sys

from swarm_forage.study import ablation
from swarm_forage.sweep import records

EXAMPLE = """example (the table of docs/FIDELITY.md, from the sweeps `make ablation` ran):
  rosrun swarm_forage ablation_table.py results/ablation/ablation_dpo_64x32 results/ablation/ablation_dpo_96x48 \\
      results/ablation/ablation_crw_96x48 --output docs/ablation/table.md --csv docs/ablation/runs.csv"""


def main(argv=None):
    ap = argparse.ArgumentParser(prog='ablation_table.py', description=__doc__, epilog=EXAMPLE,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('folders', nargs='+', help='the ablation\'s sweep folders, one arm each, in the table\'s order')
    ap.add_argument('--output', required=True, help='the markdown file to write')
    ap.add_argument('--csv', help='also write one line per record to this CSV file')
    ap.add_argument('--note', default='', help='a line on how the runs were made, under the title')
    ap.add_argument('--partial', action='store_true', help='make the table of sweeps that have not finished (it '
                    'says so); without it such a sweep is refused')
    ap.add_argument('--claim-d-sizes', metavar='ARENA,N_DPO,N_CRW', help='claim (d)\'s groups (default: 96x48,2048,'
                    '8192, the paper\'s)')
    a = ap.parse_args(argv)
    sizes = None
    if a.claim_d_sizes:
        words = a.claim_d_sizes.split(',')
        if len(words) != 3 or not words[1].isdigit() or not words[2].isdigit():
            ap.error('--claim-d-sizes: want ARENA,N_DPO,N_CRW, e.g. 96x48,2048,8192 (got %s)' % a.claim_d_sizes)
        sizes = (words[0], int(words[1]), int(words[2]))
    lacking = records.incomplete(a.folders)
    if lacking and not a.partial:
        print('ablation_table.py: the sweeps have not finished: %s; run them to their end (paper --ablation), or give '
              '--partial' % '; '.join(lacking), file=sys.stderr)
        return 1
    note = a.note + (' ' if a.note else '') + ('**Partial:** %s.' % '; '.join(lacking) if lacking else '')
    try:
        verdicts = ablation.write(a.folders, a.output, a.csv, note=note.strip(), sizes=sizes)
    except ablation.AblationError as err:
        print('ablation_table.py: %s' % err, file=sys.stderr)
        return 1
    print(a.output)
    for row, c in verdicts.items():
        print('(d) %s: %s%s' % (row, c.verdict, '' if c.verdict == 'not measured' else ': q = %.3f [%.3f, %.3f], %s '
                                'seeds' % (c.estimate, c.low, c.high, c.seeds_text())))
    return 0


if __name__ == '__main__':  # paper runs it so, a process of its own
    sys.exit(main())
