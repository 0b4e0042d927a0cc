#!/usr/bin/env python3
# SPDX-License-Identifier: BSD-3-Clause
"""Checks that a tree's layers only point down, from its object files: no
object of a folder references a symbol defined in a folder above it, and no
objects reference each other (directly or around a longer cycle).

usage: mk/layers.py ROOT "LAYER..." OBJ... [--place OBJ=LAYER]...

ROOT is where the tree's objects are built (build/obj/host); the LAYERs are
its folders, lowest first (for host/, HOST_DIRS in mk/host.mk: the one place
its order is written). Objects directly in ROOT (main.o) are the top layer.
Folders of one rank are named together with a comma ("bin,gcl"): they may
not reference each other either. --place puts an object built elsewhere
(the generated web page table) in a layer.

Prints each upward reference as 'upward: OBJ (layer) -> SYMBOL in OBJ
(layer)' and each cycle as 'cycle: OBJ -> OBJ -> ... -> OBJ', then one line
of totals; exits 1 when there is any.
"""
import os
import subprocess
import sys


def symbols(obj):
    """(defined, undefined) global symbols of one object file."""
    out = subprocess.run(["nm", "-g", obj], check=True, capture_output=True, text=True).stdout
    defined, undefined = set(), set()
    for line in out.splitlines():
        fields = line.split()
        if len(fields) == 2 and fields[0] == "U":
            undefined.add(fields[1])
        elif len(fields) == 3 and fields[1] not in "Uw":
            defined.add(fields[2])
    return defined, undefined


def layer_objects(root, layers, objects, placed_elsewhere):
    """{object path: (rank, layer name)}, the root's own objects on top."""
    rank_of = {}
    for rank, group in enumerate(layers):
        for name in group.split(","):
            rank_of[name] = (rank, name)
    placed = {}
    for obj in objects:
        folder = os.path.dirname(os.path.relpath(obj, root)).split(os.sep)[0]
        if obj in placed_elsewhere:
            placed[obj] = rank_of[placed_elsewhere[obj]]
        elif folder == "":
            placed[obj] = (len(layers), "top")
        elif folder in rank_of:
            placed[obj] = rank_of[folder]
        else:
            sys.exit(f"layers: {obj} is in no layer (add its folder to the order)")
    return placed


def find_cycles(edges):
    """A cycle through each group of objects that reach each other, found
    by a depth-first walk from every object in name order."""
    cycles, seen = [], set()
    state = {}

    def walk(node, stack):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(edges.get(node, ())):
            if state.get(nxt) == "open":
                cycle = stack[stack.index(nxt):]
                key = frozenset(cycle)
                if key not in seen:
                    seen.add(key)
                    cycles.append(cycle + [nxt])
            elif nxt not in state:
                walk(nxt, stack)
        stack.pop()
        state[node] = "done"

    for node in sorted(edges):
        if node not in state:
            walk(node, [])
    return cycles


def main(argv):
    placed_elsewhere = {}
    while "--place" in argv:
        i = argv.index("--place")
        obj, _, layer = argv[i + 1].partition("=")
        placed_elsewhere[obj] = layer
        del argv[i:i + 2]
    if len(argv) < 3:
        sys.exit(__doc__)
    root, layers, objects = argv[0], argv[1].split(), argv[2:]
    placed = layer_objects(root, layers, objects, placed_elsewhere)
    table = {obj: symbols(obj) for obj in placed}
    definer = {}
    for obj, (defined, _) in table.items():
        for sym in defined:
            definer[sym] = obj

    upward = []
    edges = {}
    for obj, (_, undefined) in sorted(table.items()):
        rank, layer = placed[obj]
        for sym in sorted(undefined):
            target = definer.get(sym)
            if target is None or target == obj:
                continue
            edges.setdefault(obj, set()).add(target)
            target_rank, target_layer = placed[target]
            if target_rank > rank or (target_rank == rank and target_layer != layer):
                upward.append(f"upward: {obj} ({layer}) -> {sym} in {target} ({target_layer})")
    cycles = find_cycles(edges)

    for line in upward:
        print(line)
    for cycle in cycles:
        print("cycle: " + " -> ".join(cycle))
    print(f"layers: {len(placed)} objects of {root} in {len(layers) + 1} layers; "
          f"{len(upward)} upward references, {len(cycles)} cycles")
    return 1 if upward or cycles else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
