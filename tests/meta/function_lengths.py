#!/usr/bin/env python3
"""Fails when a function body in the given C++ trees is longer than LIMIT lines (house style:
functions of at most 120 lines; split a longer one into named steps).

    tests/meta/function_lengths.py LIMIT DIR...

A function is a brace block opened after a parameter list ')' (with const, noexcept, override or
a trailing return type between) outside any other function, not after if/for/while/switch/catch;
lambdas count towards the function they sit in. Comments and string literals are skipped.
Prints the offenders, longest first, as FILE:LINE: N lines.
"""
import os
import re
import sys


def strip(s):
    """s without comments and string or character literals; newlines kept."""
    out, i, n = [], 0, len(s)
    while i < n:
        if s.startswith("//", i):
            j = s.find("\n", i)
            i = n if j < 0 else j
        elif s.startswith("/*", i):
            j = s.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * s.count("\n", i, j))
            i = j
        elif s.startswith('R"', i) and re.match(r'R"([^(\s]*)\(', s[i:]):
            d = re.match(r'R"([^(\s]*)\(', s[i:]).group(1)
            j = s.find(")" + d + '"', i)
            j = n if j < 0 else j + len(d) + 2
            out.append('""' + "\n" * s.count("\n", i, j))
            i = j
        elif s[i] in "\"'":
            q, j = s[i], i + 1
            while j < n and s[j] != q and s[j] != "\n":
                j += 2 if s[j] == "\\" else 1
            out.append(q + q)
            i = j + 1
        else:
            out.append(s[i])
            i += 1
    return "".join(out)


def opens_function(text, at):
    """Whether the '{' at `at` opens a function body."""
    pre = text[max(0, at - 600):at].rstrip()
    pre = re.sub(r"(const|noexcept|override|final|mutable)\s*$", "", pre).rstrip()
    pre = re.sub(r"->\s*[\w:<>,\s&*]+$", "", pre).rstrip()
    if not pre.endswith(")"):
        return False
    depth, j = 0, len(pre) - 1
    while j >= 0:
        if pre[j] == ")":
            depth += 1
        elif pre[j] == "(":
            depth -= 1
            if depth == 0:
                break
        j -= 1
    m = re.search(r"(\w+)\s*$", pre[:j])
    return bool(m) and m.group(1) not in ("if", "for", "while", "switch", "catch")


def long_functions(path, limit):
    text = strip(open(path, encoding="utf-8", errors="replace").read())
    stack, found = [], []
    for i, c in enumerate(text):
        if c == "{":
            in_function = any(kind == "function" for kind, _ in stack)
            stack.append(("function" if not in_function and opens_function(text, i) else "block", i))
        elif c == "}" and stack:
            kind, start = stack.pop()
            if kind == "function":
                first, last = text.count("\n", 0, start) + 1, text.count("\n", 0, i) + 1
                if last - first + 1 > limit:
                    found.append((last - first + 1, path, first))
    return found


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        return 2
    limit = int(sys.argv[1])
    found = []
    for root in sys.argv[2:]:
        for d, _, files in os.walk(root):
            for f in sorted(files):
                if f.endswith((".cpp", ".hpp", ".h")):
                    found += long_functions(os.path.join(d, f), limit)
    for n, path, line in sorted(found, reverse=True):
        print(f"{path}:{line}: {n} lines (limit {limit})")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
