"""Experiment files (config/experiments/*.yaml), checked against this build and planned into runs.

kinds: the controller kinds this build lists; models: its models and quirks, and the model as an axis; file:
an experiment file loaded and checked; plan: its runs, each with its words, group and key (the core's)."""


class ExperimentError(ValueError):
    """A bad experiment file or choice, naming the key and what is valid."""
