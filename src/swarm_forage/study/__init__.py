"""The paper's study: its command (paper, with its steps and publish), the claim-by-claim report (report), the
claims and their verdicts (claims: the rule and thresholds; paper_claims: claims (a)-(e)), a sweep's bootstrap
over seeds (bootstrap) and each point's interval (intervals), the ablation (ablation, ablation_table), where each
claim turns (claim_variants) and the results table of both models (models_table)."""
