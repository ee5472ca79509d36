"""Hostile text shared by the untrusted-input tests: the injection strings of the expression reader and a xacro
expression that starts a process.  Each payload, if it ever ran, would leave a file named ``MARKER`` or
``SENTINEL`` in the working directory, which the tests look for."""

MARKER = "MARKER"

INJECTIONS = [
    f"__import__('os').system('touch {MARKER}')",
    "().__class__.__bases__",
    "().__class__.__bases__[0].__subclasses__()",
    "lambda: 0",
    f"exec('open(\"{MARKER}\", \"w\")')",
    f"open('{MARKER}','w')",
    "globals()",
    "eval('1')",
    "getattr(x, 'y')",
    "x.__class__",
    '"a"*10',
    "1 if 1 else 0",
    "[1][0]",
    "__builtins__",
    "Symbol('x')",
    "sin(x=1)",
    "(1).real",
    "f'{1}'",
    "9**9**9**9",            # would not finish: refused before SymPy computes it
    "sqrt(" + "7" * 1990 + ")",  # seconds of trial division
    "1e-99999999",           # a denominator of 10**99999999
    "1 + " * 300_000 + "1",  # 1.2 MB
    "(" * 10_000 + "1" + ")" * 10_000,
    "(" * 150 + "1" + ")" * 150,
    "-" * 1_500 + "1",
    "Min(" + ",".join(f"x{i}" for i in range(300)) + ")",   # minutes of pairwise comparisons
]

# xacro evaluates ${...} with Python's eval and no builtins, yet python.vars and python.type reach every class loaded,
# subprocess.Popen among them (issue 37): this expression, expanded, runs `touch SENTINEL` in the working directory.
RUNS = ("${[c for c in python.vars(python.type)['__subclasses__'](python.type.mro(python.type)[-1]) "
        "if python.repr(c) == \"<class 'subprocess.Popen'>\"][0](['touch', 'SENTINEL']).wait()}")
