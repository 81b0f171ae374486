#!/usr/bin/env python3
"""paper_report.py --ideal DIR ... --output REPORT.md: the paper's claims against measured sweeps, claim by
claim (swarm_forage.study.report)."""
import sys

from swarm_forage.study import report

if __name__ == '__main__':
    sys.exit(report.main())
