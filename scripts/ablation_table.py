#!/usr/bin/env python3
"""ablation_table.py SWEEP_DIR ... --output TABLE.md: the ablation table of FORDYCA 2019's quirks
(swarm_forage.study.ablation_table)."""
import sys

from swarm_forage.study import ablation_table

if __name__ == '__main__':
    sys.exit(ablation_table.main())
