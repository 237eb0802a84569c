#!/usr/bin/env python3
"""Lists functions longer than a limit (default 80 lines) in C++ sources, and exits 1 when there are any.

A function is a definition that starts at column 0 (free functions, member functions defined out of line) or at
the indentation of a class body, and ends at the matching closing brace; its length counts its lines from the
signature's first line to the closing brace, as a reader scrolls them. Comments and blank lines count too.
  python3 scripts/check_function_length.py [--max N] [PATH ...]   (default: src plugins firmware)
"""
import argparse
import pathlib
import re
import sys

START = re.compile(r'^(\s{0,2})(?!(?:if|for|while|switch|return|else|do|case|namespace|struct|class|enum|union)\b)'
                   r'[A-Za-z_~][\w:<>,\s\*&~\[\]]*\([^;]*$')


def strip_strings_and_comments(line, in_block):
    out, i = [], 0
    while i < len(line):
        if in_block:
            end = line.find('*/', i)
            if end < 0:
                return ''.join(out), True
            i, in_block = end + 2, False
        elif line.startswith('//', i):
            break
        elif line.startswith('/*', i):
            in_block, i = True, i + 2
        elif line[i] in '"\'':
            quote, i = line[i], i + 1
            while i < len(line) and line[i] != quote:
                i += 2 if line[i] == '\\' else 1
            i += 1
        else:
            out.append(line[i])
            i += 1
    return ''.join(out), in_block


def long_functions(path, limit):
    lines = path.read_text(errors='replace').splitlines()
    found, i, in_block = [], 0, False
    raw = r'R"('
    while i < len(lines):
        code, in_block = strip_strings_and_comments(lines[i], in_block)
        if START.match(code) and raw not in lines[i]:
            # Find the body's opening brace within the signature's next few lines.
            j, depth, opened, signature_code = i, 0, False, code
            while j < len(lines) and j < i + 8:
                c = code if j == i else strip_strings_and_comments(lines[j], False)[0]
                if ';' in c and '{' not in c and not opened:
                    break
                if '{' in c:
                    opened = True
                    break
                j += 1
            if opened:
                depth, k = 0, j
                while k < len(lines):
                    c = strip_strings_and_comments(lines[k], False)[0] if k != i else code
                    depth += c.count('{') - c.count('}')
                    if depth <= 0 and '}' in c:
                        break
                    k += 1
                length = k - i + 1
                if length > limit:
                    found.append((i + 1, length, signature_code.strip()[:90]))
                i = k + 1
                continue
        i += 1
    return found


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument('--max', type=int, default=80)
    parser.add_argument('paths', nargs='*', default=['src', 'plugins', 'firmware'])
    args = parser.parse_args()
    total = 0
    for root in args.paths:
        root = pathlib.Path(root)
        files = [root] if root.is_file() else sorted(p for p in root.rglob('*') if p.suffix in ('.cc', '.h', '.cpp'))
        for f in files:
            for line, length, signature in long_functions(f, args.max):
                print(f'{f}:{line}: {length} lines: {signature}')
                total += 1
    print(f'check_function_length: {total} function(s) over {args.max} lines')
    return 1 if total else 0


if __name__ == '__main__':
    sys.exit(main())
