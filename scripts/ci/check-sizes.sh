#!/usr/bin/env python3
# Lists every Rust source file over 800 lines and every function over 80 lines, one a line
# as `path:line: name (N lines)`, and exits 1 if there is any.
#
#   scripts/ci/check-sizes.sh            # the workspace's .rs files (git's list, no target/)
#   scripts/ci/check-sizes.sh FILE...    # just these files
#
# A file's size is its line count (`wc -l`). A function spans from the line of its `fn` to
# the line of its closing brace, both counted; closures and nested items count toward the
# function that holds them (a nested `fn` is also measured on its own); `#[test]` functions
# count like any other. The scan matches braces with string, raw string, char literals and
# comments skipped, so a `fn` or a brace inside one of them is not seen; a `fn` with no
# body (a trait method's declaration) and a `fn(..)` pointer type are not functions.
# Plain python3, no dependencies.
import os
import subprocess
import sys

MAX_FILE_LINES = 800
MAX_FN_LINES = 80


def code_tokens(text):
    """Yields (offset, char) for every character outside comments, strings and char
    literals: what the brace matcher and the `fn` finder look at."""
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if c == "/" and text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
            continue
        if c == "/" and text.startswith("/*", i):
            depth, i = 1, i + 2
            while i < n and depth:
                if text.startswith("/*", i):
                    depth, i = depth + 1, i + 2
                elif text.startswith("*/", i):
                    depth, i = depth - 1, i + 2
                else:
                    i += 1
            continue
        raw = raw_string_end(text, i)
        if raw is not None:
            i = raw
            continue
        if c == '"' or (c == "b" and text.startswith('b"', i) and not ident_before(text, i)):
            i = text.index('"', i) + 1
            while i < n and text[i] != '"':
                i += 2 if text[i] == "\\" else 1
            i += 1
            continue
        if c == "'":
            # A char literal ('x', '\n', '\u{1F600}', '"'), or a lifetime / label ('a).
            if text.startswith("\\", i + 1):
                j = i + 3  # past the escaped character, which may itself be a quote
                while j < n and text[j] != "'":
                    j += 1
                i = j + 1
                continue
            if i + 2 < n and text[i + 2] == "'":
                i += 3
                continue
            yield i, c
            i += 1
            continue
        yield i, c
        i += 1


def ident_before(text, i):
    return i > 0 and (text[i - 1].isalnum() or text[i - 1] == "_")


def raw_string_end(text, i):
    """The offset past a raw string (r"..", r#".."#, br#".."#) that starts at i, or None."""
    j = i
    if text.startswith("br", j):
        j += 2
    elif text.startswith("r", j):
        j += 1
    else:
        return None
    if ident_before(text, i):
        return None
    hashes = 0
    while j < len(text) and text[j] == "#":
        hashes, j = hashes + 1, j + 1
    if j >= len(text) or text[j] != '"':
        return None
    close = '"' + "#" * hashes
    end = text.find(close, j + 1)
    return len(text) if end < 0 else end + len(close)


def is_ident(c):
    return c.isalnum() or c == "_"


def functions(text):
    """Yields (name, first line, line count) for every function with a body."""
    toks = list(code_tokens(text))
    code = "".join(c for _, c in toks)
    offsets = [o for o, _ in toks]
    line_starts = [0]
    for k, ch in enumerate(text):
        if ch == "\n":
            line_starts.append(k + 1)

    def line_of(off):
        lo, hi = 0, len(line_starts) - 1
        while lo < hi:
            mid = (lo + hi + 1) // 2
            if line_starts[mid] <= off:
                lo = mid
            else:
                hi = mid - 1
        return lo + 1

    # Matching braces, by position in `code`.
    close_of, stack = {}, []
    for k, ch in enumerate(code):
        if ch == "{":
            stack.append(k)
        elif ch == "}" and stack:
            close_of[stack.pop()] = k

    k, n = 0, len(code)
    while True:
        k = code.find("fn", k)
        if k < 0:
            return
        start, k = k, k + 2
        if (start > 0 and is_ident(code[start - 1])) or k >= n or not code[k].isspace():
            continue
        j = k
        while j < n and code[j].isspace():
            j += 1
        if code.startswith("r#", j):
            j += 2
        name_start = j
        while j < n and is_ident(code[j]):
            j += 1
        if j == name_start:
            continue  # `fn(` pointer types, `fn $name` in macros
        name = code[name_start:j]
        # The body is the first `{` outside parentheses and brackets; a `;` there first
        # means a declaration with no body.
        depth = 0
        while j < n:
            ch = code[j]
            if ch in "([":
                depth += 1
            elif ch in ")]":
                depth -= 1
            elif depth == 0 and ch == ";":
                j = -1
                break
            elif depth == 0 and ch == "{":
                break
            j += 1
        if j < 0 or j >= n or j not in close_of:
            continue
        first = line_of(offsets[start])
        last = line_of(offsets[close_of[j]])
        yield name, first, last - first + 1


def rust_files(root):
    try:
        out = subprocess.run(
            ["git", "ls-files", "--cached", "--others", "--exclude-standard", "*.rs"],
            cwd=root, check=True, capture_output=True, text=True,
        ).stdout
        files = [f for f in out.splitlines() if os.path.exists(os.path.join(root, f))]
    except (OSError, subprocess.CalledProcessError):
        files = []
        for d, dirs, names in os.walk(root):
            dirs[:] = [x for x in dirs if x not in ("target", ".git")]
            files += [os.path.relpath(os.path.join(d, f), root) for f in names if f.endswith(".rs")]
    return sorted(f for f in files if not f.startswith("target/") and "/target/" not in f)


def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    files = argv[1:] or rust_files(root)
    bad = 0
    for path in files:
        full = path if os.path.isabs(path) or argv[1:] else os.path.join(root, path)
        with open(full, encoding="utf-8") as f:
            text = f.read()
        lines = text.count("\n") + (0 if text.endswith("\n") or not text else 1)
        if lines > MAX_FILE_LINES:
            print(f"{path}:1: file ({lines} lines, limit {MAX_FILE_LINES})")
            bad += 1
        for name, line, count in functions(text):
            if count > MAX_FN_LINES:
                print(f"{path}:{line}: {name} ({count} lines, limit {MAX_FN_LINES})")
                bad += 1
    sys.stdout.flush()
    if bad:
        print(f"{bad} over the limits (files {MAX_FILE_LINES} lines, functions {MAX_FN_LINES})",
              file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
