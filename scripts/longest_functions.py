#!/usr/bin/env python3
"""Lists the longest function bodies in C++ sources (issue 25: "the largest function in host/src is
under 150 lines"). A brace counter, not a parser: comments, strings and character literals are blanked,
then every '{' that opens at namespace or class level after a parameter list (')', optionally followed
by const, override, noexcept, final, a trailing return type or a constructor's initializer list) starts
a function, which ends at its matching '}'. Lambdas and local classes count toward the function that
holds them.

    scripts/longest_functions.py [--top N] [--over LINES] PATH...   (folders are searched for .cpp/.hpp/.inc)
"""
import argparse
import os
import re
import sys

EXTENSIONS = (".cpp", ".hpp", ".h", ".cc", ".inc")


def blank(text):
    """The text with comments, string and character literals replaced by spaces (newlines kept)."""
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
            out.append("".join(ch if ch == "\n" else " " for ch in text[i:j]))
            i = j
        elif c == "R" and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            m = re.match(r'R"([^()\\ ]{0,16})\(', text[i:])
            if not m:
                out.append(c)
                i += 1
                continue
            end = ")" + m.group(1) + '"'
            j = text.find(end, i + m.end())
            j = n if j < 0 else j + len(end)
            out.append('""' + "".join(ch if ch == "\n" else " " for ch in text[i + 2:j]))
            i = j
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum() and text[i - 1:i + 2] != "u8'":
                out.append(c)  # a digit separator (1'000)
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + " " * (min(j, n) - i - 1) + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


HEAD_END = re.compile(
    r"\)\s*(const\s*)?(&{1,2}\s*)?(noexcept(\s*\([^)]*\))?\s*)?(override\s*)?(final\s*)?(->\s*[\w:<>,\s*&]+)?$")
INIT_LIST = re.compile(r"\)\s*:\s*[\w:]+\s*[({].*$", re.S)
SCOPE = re.compile(r"\b(namespace|class|struct|union|enum)\b[^;{()]*$")
NAME = re.compile(r"([~\w:<>]+(?:operator\s*\S+)?)\s*\($")


def functions(path):
    text = blank(open(path, encoding="utf-8", errors="replace").read())
    stack = []  # (kind, start index, name)
    found = []
    last = 0  # start of the text since the last ';', '{' or '}'
    for i, c in enumerate(text):
        if c == ";":
            last = i + 1
        elif c == "{":
            head = text[last:i].strip()
            in_function = any(k == "function" for k, _, _ in stack)
            kind = "other"
            if in_function:
                kind = "other"
            elif SCOPE.search(head) and not head.rstrip().endswith(")"):
                kind = "scope"
            elif HEAD_END.search(head) or INIT_LIST.search(head) or (
                    stack and stack[-1][0] == "init" and head.endswith(")")):
                kind = "function"
            elif re.search(r"\)\s*:\s*", head) and not in_function:
                # an initializer list with braces (a_{x}): the body is the brace after a ')' or '}'
                kind = "init"
            name = ""
            if kind == "function":
                paren = depth_open_paren(head)
                name = NAME.search(head[:paren + 1]).group(1) if paren >= 0 and NAME.search(head[:paren + 1]) else "?"
            stack.append((kind, i, name))
            last = i + 1
        elif c == "}":
            if stack:
                kind, start, name = stack.pop()
                if kind == "function":
                    first = text.count("\n", 0, start) + 1
                    end = text.count("\n", 0, i) + 1
                    found.append((end - first + 1, path, first, name))
                elif kind == "init" and stack is not None:
                    # a braced member initializer inside the list: the list goes on
                    pass
            last = i + 1
    return found


def depth_open_paren(head):
    """Index of the '(' that opens the last top-level parameter list of a function head."""
    depth = 0
    for k in range(len(head) - 1, -1, -1):
        if head[k] == ")":
            depth += 1
        elif head[k] == "(":
            depth -= 1
            if depth == 0:
                # skip an initializer list: the parameter list is the one before ':'
                before = head[:k].rstrip()
                if re.search(r"[:,]\s*[\w:]+$", before) and ")" in before:
                    colon = before.rfind(")")
                    return depth_open_paren(head[:colon + 1])
                return k
    return -1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("paths", nargs="+")
    ap.add_argument("--top", type=int, default=15)
    ap.add_argument("--over", type=int, default=0, help="list every function longer than this instead")
    a = ap.parse_args()
    files = []
    for p in a.paths:
        if os.path.isdir(p):
            for root, _, names in os.walk(p):
                files += [os.path.join(root, f) for f in names if f.endswith(EXTENSIONS)]
        else:
            files.append(p)
    found = []
    for f in sorted(files):
        found += functions(f)
    found.sort(key=lambda t: (-t[0], t[1], t[2]))
    shown = [t for t in found if t[0] > a.over] if a.over else found[:a.top]
    for lines, path, first, name in shown:
        print(f"{lines:5d}  {path}:{first}  {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
