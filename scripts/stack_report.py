#!/usr/bin/env python3
"""Worst-case stack of the core's public entry points, from GCC's -fcallgraph-info=su files.

usage: stack_report.py [--limit BYTES] [--top N] FILE.ci...

Each function's own frame comes from its "N bytes (static)" label; the worst case of a
function is its frame plus the worst of the functions it calls directly, over the whole call
graph. Calls through function pointers (sinks, callbacks) are not in the graph and so not
counted; library functions (memcpy, snprintf, ...) count 0 (the image's libc is nano newlib);
a recursive cycle is reported and counted once round. Prints the entry points (kelp_*
functions with external linkage) over the limit and the largest ones, with the deepest chain.
"""
import re
import sys

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"')
SIZE = re.compile(r'\\n(\d+) bytes \((static|dynamic|dynamic,bounded)\)')


def main(argv):
    limit, top, files, fail = 1024, 12, [], False
    i = 0
    while i < len(argv):
        if argv[i] == '--limit':
            limit = int(argv[i + 1]); i += 2
        elif argv[i] == '--top':
            top = int(argv[i + 1]); i += 2
        elif argv[i] == '--fail':
            fail = True; i += 1
        else:
            files.append(argv[i]); i += 1
    frame, kind, calls = {}, {}, {}
    for f in files:
        with open(f, encoding='utf-8', errors='replace') as fh:
            for line in fh:
                m = NODE.search(line)
                if m:
                    title, label = m.group(1), m.group(2)
                    s = SIZE.search(label)
                    if s:
                        frame[title] = int(s.group(1))
                        kind[title] = s.group(2)
                    continue
                m = EDGE.search(line)
                if m:
                    calls.setdefault(m.group(1), set()).add(m.group(2))
    memo, recursive = {}, set()

    def worst(fn, path):
        if fn in memo:
            return memo[fn]
        if fn in path:
            recursive.add(fn)
            return (0, [])
        path.add(fn)
        best, chain = 0, []
        for callee in calls.get(fn, ()):
            w, c = worst(callee, path)
            if w > best:
                best, chain = w, c
        path.discard(fn)
        res = (frame.get(fn, 0) + best, [fn] + chain)
        memo[fn] = res
        return res

    sys.setrecursionlimit(10000)
    entries = sorted(t for t in frame if t.startswith('kelp_') and ':' not in t)
    rows = [(worst(e, set())[0], e, worst(e, set())[1]) for e in entries]
    rows.sort(reverse=True)
    over = [r for r in rows if r[0] > limit]
    print(f"stack: {len(rows)} public core entry points; worst case {rows[0][0] if rows else 0} bytes "
          f"({rows[0][1] if rows else '-'}); {len(over)} over {limit} bytes")
    for w, e, chain in rows[:top]:
        short = ' > '.join(c.split(':')[-1] for c in chain[:6]) + (' > ...' if len(chain) > 6 else '')
        print(f"  {w:7d}  {e:42s} {short}")
    dyn = sorted(t for t, k in kind.items() if k != 'static')
    if dyn:
        print("  dynamic frames (not bounded at compile time): " + ', '.join(dyn))
    if recursive:
        print("  recursive (one round counted): " + ', '.join(sorted(c.split(':')[-1] for c in recursive)))
    if fail and over:
        print(f"stack: {len(over)} public entry points need more than {limit} bytes")
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))
