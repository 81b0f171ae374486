"""A Python controller that does nothing (bench_python): what remains of its tick is the interpreter's cost."""


class Idle:
    defaults = 'bench_python_idle.yaml'
    states = ['idle']

    def __init__(self, constants, seed, first_id, count, world):
        pass

    def step(self, tick, s, out):
        pass
