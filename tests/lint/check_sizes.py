#!/usr/bin/env python3
"""Size lint: no source file over --max-file-lines, no function over --max-function-lines.

A function is counted from the line of its opening brace to the line of its
closing brace (the body). Lambdas and local classes count towards the function
that holds them. Comments, string and character literals are blanked before the
braces are matched, so a brace in a string does not confuse the count.

Usage: check_sizes.py ROOT [--max-file-lines 800] [--max-function-lines 80]
Exit 1 with one line per offence (file:line: what), 0 when everything fits.
"""
import argparse
import os
import re
import sys

LAYERS = ("core", "nav", "sim", "scenarios", "tests")
CONTROL = re.compile(r"\b(if|for|while|switch|catch|do|else|try)\s*$")
CONTROL_CALL = re.compile(r"\b(if|for|while|switch|catch)\s*\(.*\)\s*$", re.S)
QUALIFIERS = re.compile(
    r"\)\s*(const|noexcept|override|final|mutable|volatile|&|&&|\s|->\s*[\w:<>,\s\*&]+"
    r"|noexcept\s*\([^)]*\))*$", re.S)
SCOPE = re.compile(r"\b(namespace|class|struct|union|enum)\b[^()]*$", re.S)


def blank_comments_and_strings(text):
    """Replaces comments and literals with spaces, keeping newlines."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = ")" + m.group(1) + '"'
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and (text[i - 1].isalnum()):  # digit separator 1'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


def functions(text):
    """Yields (name, first_line, line_count) of every function body in text."""
    code = blank_comments_and_strings(text)
    code = re.sub(r"^\s*#.*$", "", code, flags=re.M)  # preprocessor lines
    stack = []  # per open brace: "scope", "function" or "block"
    starts = []
    last_stop = 0
    for i, c in enumerate(code):
        if c == "{":
            head = code[last_stop:i].strip()
            inside_function = "function" in stack
            if inside_function:
                kind = "block"
            elif SCOPE.search(head) or head.endswith("extern \"C\"") or head == "":
                kind = "scope" if SCOPE.search(head) else "block"
            elif (QUALIFIERS.search(head) or re.search(r"\)\s*:\s*.*$", head, re.S)) and \
                    not CONTROL_CALL.search(head) and not CONTROL.search(head) and \
                    not head.endswith("="):
                kind = "function"
            else:
                kind = "block"
            stack.append(kind)
            starts.append((i, head))
            last_stop = i + 1
        elif c == "}":
            if stack:
                kind = stack.pop()
                start, head = starts.pop()
                if kind == "function":
                    first = code.count("\n", 0, start) + 1
                    last = code.count("\n", 0, i) + 1
                    name = re.findall(r"([~\w:]+)\s*\(", head)
                    yield (name[0] if name else "?"), first, last - first + 1
            last_stop = i + 1
        elif c == ";":
            last_stop = i + 1


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("root")
    parser.add_argument("--max-file-lines", type=int, default=800)
    parser.add_argument("--max-function-lines", type=int, default=80)
    parser.add_argument("--report", action="store_true", help="list the longest functions")
    args = parser.parse_args()
    offences, lengths = [], []
    for layer in LAYERS:
        for folder, _, files in os.walk(os.path.join(args.root, layer)):
            for name in sorted(files):
                if not name.endswith((".h", ".cc")):
                    continue
                path = os.path.join(folder, name)
                rel = os.path.relpath(path, args.root)
                with open(path, encoding="utf-8") as f:
                    text = f.read()
                lines = text.count("\n")
                if lines > args.max_file_lines:
                    offences.append(f"{rel}:1: {lines} lines (limit {args.max_file_lines})")
                for fn, line, count in functions(text):
                    lengths.append((count, f"{rel}:{line}: {fn}"))
                    if count > args.max_function_lines:
                        offences.append(f"{rel}:{line}: function {fn} is {count} lines "
                                        f"(limit {args.max_function_lines})")
    if args.report:
        for count, where in sorted(lengths, reverse=True)[:40]:
            print(f"{count:5d} {where}")
    for o in offences:
        print(o)
    return 1 if offences else 0


if __name__ == "__main__":
    sys.exit(main())
