#!/usr/bin/env python3
"""Every source names the standard header of what it uses, itself or through the project's own
headers it includes: a unity build (the ci and sanitize presets) compiles a file after others
whose includes it silently borrows, and the release preset, which is not a unity build, then fails
(tools/viaduct/cmd_ident.cpp used std::cerr without <iostream>: scripts/demo.sh stopped at its
build from 6480180 to 0740b0b while CI passed).

  direct_includes.py ROOT

Checks the facilities in RULES (a list, not a compiler: it catches the usual borrowings; headers
of other libraries and the standard headers' own includes are not followed).
"""
import os
import re
import sys

RULES = {
    "iostream": r"\bstd::(cerr|cout|clog|cin)\b",
    "sstream": r"\bstd::(ostringstream|istringstream|stringstream)\b",
    "fstream": r"\bstd::(ifstream|ofstream|fstream)\b",
    "iomanip": r"\bstd::(setprecision|setw|setfill|put_time|get_time)\b",
    "functional": r"\bstd::function\b",
    "memory": r"\bstd::(unique_ptr|shared_ptr|make_unique|make_shared)\b",
    "map": r"\bstd::map\b",
    "set": r"\bstd::set\b",
    "unordered_map": r"\bstd::unordered_map\b",
    "optional": r"\bstd::optional\b",
    "thread": r"\bstd::thread\b",
    "mutex": r"\bstd::(mutex|lock_guard|unique_lock)\b",
    "atomic": r"\bstd::atomic\b",
    "chrono": r"\bstd::chrono\b",
    "numeric": r"\bstd::(accumulate|iota|inner_product)\b",
    "filesystem": r"\bstd::filesystem\b",
    "regex": r"\bstd::regex\b",
    "array": r"\bstd::array\b",
    "deque": r"\bstd::deque\b",
    "limits": r"\bstd::numeric_limits\b",
    "cstring": r"\bstd::(memcpy|strlen|strcmp|memset)\b",
}
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.M)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    root = os.path.abspath(sys.argv[1])
    cache = {}

    def resolve(path, name, quote):
        here = [os.path.join(os.path.dirname(path), name)] if quote == '"' else []
        for c in here + [os.path.join(root, "include", name), os.path.join(root, "src", name)]:
            if os.path.isfile(c):
                return os.path.normpath(c)
        return None

    def standard_headers(path, seen):
        if path in cache:
            return cache[path]
        seen.add(path)
        out = set()
        with open(path, encoding="utf-8", errors="replace") as f:
            text = f.read()
        for quote, name in INCLUDE.findall(text):
            own = resolve(path, name, quote)
            if own is None:
                out.add(name)
            elif own not in seen:
                out |= standard_headers(own, seen)
        cache[path] = out
        return out

    findings = []
    for top in ("src", "tools", "include", "tests", "python"):
        for dirpath, _, files in os.walk(os.path.join(root, top)):
            for name in sorted(files):
                if not name.endswith((".cpp", ".hpp", ".h")):
                    continue
                path = os.path.normpath(os.path.join(dirpath, name))
                with open(path, encoding="utf-8", errors="replace") as f:
                    code = re.sub(r"//.*", "", f.read())
                have = standard_headers(path, set())
                for header, pattern in RULES.items():
                    m = re.search(pattern, code)
                    if m and header not in have:
                        findings.append(f"{os.path.relpath(path, root)}: {m.group(0)} without <{header}>")
    for f in findings:
        print("FAIL:", f)
    print(f"{len(findings)} source(s) borrow a standard header")
    return 1 if findings else 0


if __name__ == "__main__":
    sys.exit(main())
