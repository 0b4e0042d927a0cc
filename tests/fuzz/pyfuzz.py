#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""A small mutational fuzzer for the Python parsers of outside input (the
targets of py_targets.py), without coverage feedback: it mutates the
target's seeds (tests/fuzz/corpus/py_NAME) with byte flips, inserts,
deletions, repeats, splices and the target's tokens, and runs each input.

  pyfuzz.py run [--time S] [--seed N] [TARGET...]   fuzz each target S s
  pyfuzz.py replay [TARGET...]                      the seeds and the
                                                    regressions (tests/fuzz/
                                                    regressions/py_NAME) once
  pyfuzz.py one TARGET FILE                         one input, its traceback

The property: the parser returns, or raises the tool's own error (each
target says which); any other exception, a warning (warnings are errors
here, numpy's too) or more than WORK_LIMIT traced lines of Python for one
input (a hang, counted as work, not timed) is a finding, written to
build/fuzz/artifacts/py_NAME-SHA1. The mutations come from --seed (default
1, printed): the same seed and time give the same inputs in the same order.
"""
import argparse
import hashlib
import os
import random
import sys
import time
import traceback
import warnings

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import py_targets  # noqa: E402

ARTIFACTS = os.path.join(HERE, "..", "..", "build", "fuzz", "artifacts")
WORK_LIMIT = 2_000_000  # traced lines per input: a parser's loop that runs away
INPUT_MAX = 16384


class WorkExceeded(BaseException):
    """More work than WORK_LIMIT for one input (not an Exception: a
    parser's `except Exception` must not swallow it)."""


def run_bounded(function, data):
    """function(data) with its traced Python lines counted."""
    count = [0]

    def tracer(frame, event, arg):
        if event == "line":
            count[0] += 1
            if count[0] > WORK_LIMIT:
                raise WorkExceeded("more than %d lines of work" % WORK_LIMIT)
        return tracer

    sys.settrace(tracer)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error")
            function(data)
    finally:
        sys.settrace(None)


def check(target, data):
    """None when the target kept its property on data, else the traceback."""
    try:
        run_bounded(target.run, data)
    except WorkExceeded:
        return traceback.format_exc()
    except Exception as err:  # noqa: BLE001 - what a finding is
        if target.allowed(err):
            return None
        return traceback.format_exc()
    return None


def inputs_in(folder):
    if not os.path.isdir(folder):
        return []
    return [os.path.join(folder, name) for name in sorted(os.listdir(folder))]


def seeds_of(name):
    return inputs_in(os.path.join(HERE, "corpus", "py_" + name))


def regressions_of(name):
    return inputs_in(os.path.join(HERE, "regressions", "py_" + name))


def read(path):
    with open(path, "rb") as f:
        return f.read()


class Mutator:
    def __init__(self, rng, seeds, tokens):
        self.rng, self.seeds, self.tokens = rng, seeds, tokens

    def mutate(self, data):
        data = bytearray(data)
        for _ in range(self.rng.randint(1, 8)):
            getattr(self, self.rng.choice(("flip", "byte", "insert", "delete", "repeat",
                                           "token", "splice", "digits")))(data)
        return bytes(data[:INPUT_MAX])

    def where(self, data):
        return self.rng.randint(0, len(data))

    def flip(self, data):
        if data:
            data[self.rng.randrange(len(data))] ^= 1 << self.rng.randrange(8)

    def byte(self, data):
        if data:
            data[self.rng.randrange(len(data))] = self.rng.choice(
                (0, 0xff, 0x80, 0xaa, 0x0a, 0x20, self.rng.randrange(256)))

    def insert(self, data):
        at = self.where(data)
        data[at:at] = bytes(self.rng.randrange(256) for _ in range(self.rng.randint(1, 4)))

    def delete(self, data):
        at = self.where(data)
        del data[at:at + self.rng.randint(1, 64)]

    def repeat(self, data):
        at = self.where(data)
        chunk = data[at:at + self.rng.randint(1, 64)]
        data[at:at] = chunk * self.rng.randint(1, 16)

    def token(self, data):
        at = self.where(data)
        token = self.rng.choice(self.tokens)
        if self.rng.random() < 0.5:
            data[at:at] = token
        else:
            data[at:at + len(token)] = token

    def splice(self, data):
        other = read(self.rng.choice(self.seeds)) if self.seeds else b""
        cut, at = self.where(other), self.where(data)
        data[at:] = other[cut:]

    def digits(self, data):
        """A number of the text replaced by another."""
        starts = [i for i, b in enumerate(data) if 0x30 <= b <= 0x39]
        if starts:
            at = self.rng.choice(starts)
            end = at
            while end < len(data) and data[end] in b"0123456789.-+e":
                end += 1
            data[at:end] = self.rng.choice((b"0", b"-0", b"nan", b"inf", b"-inf", b"1e309",
                                            b"99999999999999999999", b"1.5", b"-1", b"",
                                            b"4294967296", b"0x10"))


def record_finding(name, data, trace):
    os.makedirs(ARTIFACTS, exist_ok=True)
    path = os.path.join(ARTIFACTS, "py_%s-%s" % (name, hashlib.sha1(data).hexdigest()))
    with open(path, "wb") as f:
        f.write(data)
    print("pyfuzz: %s: finding, input in %s:\n%s" % (name, os.path.abspath(path), trace),
          flush=True)


def fuzz(name, seconds, seed):
    target = py_targets.TARGETS[name]
    seeds = seeds_of(name)
    rng = random.Random("%d:%s" % (seed, name))
    mutator = Mutator(rng, seeds, target.tokens)
    pool = [read(p) for p in seeds] or [b""]
    end, runs = time.monotonic() + seconds, 0
    while time.monotonic() < end:
        data = mutator.mutate(rng.choice(pool))
        runs += 1
        trace = check(target, data)
        if trace is not None:
            record_finding(name, data, trace)
            print("pyfuzz: %s: stopped after %d inputs (--seed %d)" % (name, runs, seed))
            return False
    print("pyfuzz: %s: %d inputs in %d s, no finding (--seed %d)" % (name, runs, seconds, seed))
    return True


def replay(name):
    target = py_targets.TARGETS[name]
    paths = seeds_of(name) + regressions_of(name)
    ok = bool(seeds_of(name))
    if not ok:
        print("pyfuzz: %s: no seeds in tests/fuzz/corpus/py_%s" % (name, name))
    for path in paths:
        trace = check(target, read(path))
        if trace is not None:
            print("pyfuzz: %s: %s:\n%s" % (name, path, trace))
            ok = False
    print("pyfuzz: %s: %d inputs replayed, %s" % (name, len(paths), "ok" if ok else "FAILED"))
    return ok


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("mode", choices=("run", "replay", "one"))
    parser.add_argument("targets", nargs="*")
    parser.add_argument("--time", type=int, default=60, help="seconds per target (run)")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_intermixed_args(argv)
    if args.mode == "one":
        name, path = args.targets
        trace = check(py_targets.TARGETS[name], read(path))
        print(trace or "pyfuzz: %s: %s keeps the property" % (name, path))
        return 1 if trace else 0
    names = args.targets or sorted(py_targets.TARGETS)
    unknown = [n for n in names if n not in py_targets.TARGETS]
    if unknown:
        parser.error("unknown targets %s (known: %s)" % (unknown, sorted(py_targets.TARGETS)))
    if args.mode == "run":
        print("pyfuzz: --seed %d, %d s per target" % (args.seed, args.time), flush=True)
        results = [fuzz(n, args.time, args.seed) for n in names]
    else:
        results = [replay(n) for n in names]
    return 0 if all(results) else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
