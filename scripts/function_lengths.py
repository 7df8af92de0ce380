#!/usr/bin/env python3
"""The product's functions longer than a limit.

A function's length is its body's lines, from the line of the opening brace to
the line of the closing brace. Lambdas and local classes count within their
enclosing function. The scanner matches braces and skips strings, characters,
comments and preprocessor lines; it is not a C++ parser, but it finds every
function definition at namespace or class scope in this code base's style.
Kernels (kernels/), tests, benchmarks, fuzz targets and examples are not
counted.

    function_lengths.py [--root DIR] [--limit N] [--allowed FILE]

Prints each function over the limit as `path:line: name: N lines` and exits 1
when one is not in the allow-list. The allow-list holds `path name` lines (`#`
starts a comment); an entry whose function is no longer over the limit is an
error too, so that the list only shrinks.
"""
import argparse
import os
import re
import sys

PRODUCT_FOLDERS = ["framework", "lenses", "elements", "eye", "systems", "retina", "targets", "calibration", "solvers",
                   "analysis", "app", "tools", "python/src"]
EXTENSIONS = (".h", ".cpp", ".inc")
SCOPE_KEYWORDS = re.compile(r"\b(namespace|class|struct|union|enum)\b")
IDENTIFIER = re.compile(r"[A-Za-z_]\w*")
STRING_PREFIX = re.compile(r"(?:u8|u|U|L)?R?$")


def product_files(root):
    for folder in PRODUCT_FOLDERS:
        for parent, dirs, names in os.walk(os.path.join(root, folder)):
            dirs.sort()
            for name in sorted(names):
                if name.endswith(EXTENSIONS):
                    yield os.path.relpath(os.path.join(parent, name), root)


def tokens(text):
    """(kind, value, line) for the code's punctuation and words: strings,
    characters, comments and preprocessor lines become nothing."""
    i, line, n = 0, 1, len(text)
    at_line_start = True
    while i < n:
        c = text[i]
        if c == "\n":
            line += 1
            i += 1
            at_line_start = True
            continue
        if c in " \t\r\f\v":
            i += 1
            continue
        if c == "#" and at_line_start:
            while i < n and text[i] != "\n":
                if text[i] == "\\" and i + 1 < n and text[i + 1] == "\n":
                    line += 1
                    i += 1
                elif text.startswith("/*", i):
                    end = text.find("*/", i + 2)
                    end = n if end < 0 else end + 2
                    line += text.count("\n", i, end)
                    i = end
                    continue
                elif text.startswith("//", i):
                    while i < n and text[i] != "\n":
                        i += 1
                    break
                i += 1
            continue
        at_line_start = False
        if text.startswith("//", i):
            while i < n and text[i] != "\n":
                i += 1
            continue
        if text.startswith("/*", i):
            end = text.find("*/", i + 2)
            end = n if end < 0 else end + 2
            line += text.count("\n", i, end)
            i = end
            continue
        if c.isdigit() or (c == "." and i + 1 < n and text[i + 1].isdigit()):
            j = i + 1
            while j < n and (text[j].isalnum() or text[j] in "_.'" or
                             (text[j] in "+-" and text[j - 1] in "eEpP")):
                j += 1
            i = j
            continue
        if c.isalpha() or c == "_":
            m = IDENTIFIER.match(text, i)
            word = m.group(0)
            j = m.end()
            if j < n and text[j] in "\"'" and STRING_PREFIX.match(word):
                i = j  # the prefix of a string or character literal
                if word.endswith("R") and text[j] == '"':
                    open_paren = text.index("(", j)
                    delimiter = ")" + text[j + 1:open_paren] + '"'
                    end = text.index(delimiter, open_paren) + len(delimiter)
                    line += text.count("\n", j, end)
                    i = end
                    yield ("literal", '""', line)
                continue
            yield ("word", word, line)
            i = j
            continue
        if c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            line += text.count("\n", i, j)
            i = j + 1
            yield ("literal", '""', line)
            continue
        if text.startswith("::", i) or text.startswith("->", i):
            yield ("punct", text[i:i + 2], line)
            i += 2
            continue
        yield ("punct", c, line)
        i += 1


def matching_close(toks, k):
    """The index of the token closing the brace at toks[k]."""
    depth = 0
    for j in range(k, len(toks)):
        value = toks[j][1]
        if value == "{":
            depth += 1
        elif value == "}":
            depth -= 1
            if depth == 0:
                return j
    return len(toks) - 1


def function_name(head):
    """The name before the parameter list in a declaration's tokens, or None
    when the head declares no function (a variable, a scope, an alias)."""
    depth = 0
    angle = 0
    for k, (kind, value, _) in enumerate(head):
        if value in ("(", "["):
            if value == "(" and depth == 0 and angle == 0 and k > 0:
                return declarator_before(head, k)
            depth += 1
        elif value in (")", "]"):
            depth -= 1
        elif depth == 0 and value == "<" and not is_operator_symbol(head, k):
            angle += 1
        elif depth == 0 and value == ">" and angle > 0 and not is_operator_symbol(head, k):
            angle -= 1
        elif depth == 0 and angle == 0 and value == "=" and not is_operator_symbol(head, k):
            return None
    return None


def is_operator_symbol(head, k):
    return any(value == "operator" for _, value, _ in head[max(0, k - 3):k])


def declarator_before(head, k):
    """`ns::Class::name`, `operator()`, `~Class` ending just before head[k]."""
    j = k - 1
    for back in range(k - 1, max(-1, k - 4), -1):
        if head[back][1] == "operator":
            j = back
            break
    else:
        if head[j][0] != "word":
            return None
    start = j
    while start >= 2 and head[start - 1][1] == "::" and head[start - 2][0] == "word":
        start -= 2
    if start >= 1 and head[start - 1][1] == "~":
        start -= 1
    name = "".join(value for _, value, _ in head[start:k])
    if name == "operator" and head[k][1] == "(":
        name = "operator()"
    return name


def functions(toks):
    """(name, first line, last line) of each function body in the tokens."""
    found = []
    head = []
    k = 0
    while k < len(toks):
        kind, value, line = toks[k]
        if value in (";", "}"):
            head = []
            k += 1
            continue
        if value != "{":
            head.append(toks[k])
            k += 1
            continue
        close = matching_close(toks, k)
        words = [v for _, v, _ in head]
        name = function_name(head)
        if name is None and (SCOPE_KEYWORDS.search(" ".join(words)) or (words and words[0] == "extern")):
            if "enum" in words:
                k = close + 1  # an enum's body holds no function
            else:
                k += 1  # a namespace's or class's body: look inside
            head = []
            continue
        if name is None:
            head = []  # a braced initializer of a variable
            k = close + 1
            continue
        if in_member_initializers(head):
            head.append(("punct", "{}", line))  # `member_{value}` before the body
            k = close + 1
            continue
        found.append((name, line, toks[close][2]))
        head = []
        k = close + 1
    return found


def in_member_initializers(head):
    """True when the head ends inside a constructor's member initializer list
    with a member's name, so the brace that follows initializes that member."""
    depth = 0
    after_parameters = False
    for kind, value, _ in head:
        if value in ("(", "["):
            depth += 1
        elif value in (")", "]"):
            depth -= 1
            if depth == 0:
                after_parameters = True
        elif depth == 0 and after_parameters and value == ":":
            last = head[-1]
            return last[0] == "word" or last[1] == ">"
    return False


def long_functions(root, limit):
    for path in product_files(root):
        with open(os.path.join(root, path), encoding="utf-8", errors="replace") as f:
            text = f.read()
        for name, first, last in functions(list(tokens(text))):
            length = last - first + 1
            if length > limit:
                yield path, first, name, length


def read_allowed(path):
    allowed = set()
    if not path:
        return allowed
    with open(path, encoding="utf-8") as f:
        for raw in f:
            entry = raw.split("#", 1)[0].split()
            if entry:
                allowed.add((entry[0], entry[1]))
    return allowed


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    parser.add_argument("--limit", type=int, default=80, help="the most lines a function may have (80)")
    parser.add_argument("--allowed", help="a file of `path name` lines allowed over the limit")
    args = parser.parse_args()
    allowed = read_allowed(args.allowed)
    over = sorted(long_functions(os.path.abspath(args.root), args.limit), key=lambda f: -f[3])
    failed = False
    for path, line, name, length in over:
        known = (path, name) in allowed
        failed |= not known
        print(f"{path}:{line}: {name}: {length} lines{' (allowed)' if known else ''}")
    stale = allowed - {(path, name) for path, _, name, _ in over}
    for path, name in sorted(stale):
        failed = True
        print(f"{args.allowed}: {path} {name} is no longer over {args.limit} lines: remove it from the list")
    if failed:
        print(f"functions over {args.limit} lines: {len(over)}; split them into named steps")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
