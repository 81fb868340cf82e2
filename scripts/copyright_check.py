#!/usr/bin/env python3
# Copyright 2026 Hexapod adaptation team
# All rights reserved.
#
# Permission is hereby granted, free of charge, to any person obtaining a copy
# of this software and associated documentation files (the "Software"), to deal
# in the Software without restriction, including without limitation the rights
# to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
# copies of the Software, and to permit persons to whom the Software is
# furnished to do so, subject to the following conditions:
#
# The above copyright notice and this permission notice shall be included in all
# copies or substantial portions of the Software.
#
# THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
# IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
# FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
# AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
# LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
# OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN THE
# SOFTWARE.
"""
Copyright headers: check them, or add the missing ones (``--fix``).

The per-package ``test_copyright.py`` runs ``ament_copyright`` where it is installed (a full
ROS 2 install; it has no PyPI wheel) and this check otherwise. A source file passes when its
first comment block (after a shebang or coding line) holds a ``Copyright <year> <holder>``
line followed by the permission notice of the package's LICENSE file. The header it writes is
the MIT file header that ``ament_copyright --add-missing`` writes, so both checks accept it.

    python scripts/copyright_check.py hexapod_sim          # list files without a valid header
    python scripts/copyright_check.py --fix hexapod_*      # add the header where it is missing
"""

from __future__ import annotations

import argparse
from pathlib import Path
import re
import sys

HOLDER = 'Hexapod adaptation team'
YEAR = 2026
#: The source files ament_copyright looks at, by suffix, plus CMakeLists.txt.
SUFFIXES = ('.py', '.cmake')
SKIP_DIRS = {'build', 'install', 'log', '__pycache__', '.venv', '.git', 'resource'}
NOTICE_START = 'Permission is hereby granted'
COPYRIGHT_LINE = re.compile(r'^copyright(?:\s+\(c\))?\s+\d{4}(?:-\d{4})?,?\s+\S', re.IGNORECASE)


def permission_notice(license_file: Path) -> str:
    """Return the permission notice of an MIT LICENSE file, from 'Permission' to the end."""
    text = license_file.read_text()
    if NOTICE_START not in text:
        raise ValueError(f'{license_file}: not an MIT license (no "{NOTICE_START}" paragraph)')
    return text[text.index(NOTICE_START) :].strip()


def _normalised(text: str) -> str:
    return ' '.join(text.split())


def header_comment(notice: str, holder: str = HOLDER, year: int = YEAR) -> str:
    """Return the header as '#' comment lines: copyright line, then the notice."""
    body = [f'Copyright {year} {holder}', 'All rights reserved.', ''] + notice.split('\n')
    return '\n'.join(f'# {line}'.rstrip() for line in body) + '\n'


def _first_comment_block(text: str) -> list[str]:
    lines = text.split('\n')
    i = 0
    while i < len(lines) and (lines[i].startswith('#!') or 'coding' in lines[i][:30]):
        i += 1
    while i < len(lines) and not lines[i].strip():
        i += 1
    block = []
    while i < len(lines) and lines[i].startswith('#'):
        block.append(lines[i][1:].strip())
        i += 1
    return block


def _copyright_lines(text: str) -> tuple[list[str], list[int]]:
    block = _first_comment_block(text)
    return block, [i for i, line in enumerate(block) if COPYRIGHT_LINE.match(line)]


def file_problem(path: Path, notice: str) -> str | None:
    """Return what is wrong with ``path``'s copyright header, or None if it is valid."""
    text = path.read_text(encoding='utf-8')
    if not text.strip():
        return None  # an empty file (e.g. an empty __init__.py) has nothing to protect
    block, lines = _copyright_lines(text)
    if not lines:
        return f'{path}: no "Copyright <year> <holder>" line in the first comment block'
    if _normalised(notice) not in _normalised('\n'.join(block[lines[0] + 1 :])):
        return f'{path}: the header does not carry the LICENSE permission notice'
    return None


def source_files(root: Path) -> list[Path]:
    """Return the files of ``root`` that need a header, sorted."""
    found = []
    for path in root.rglob('*'):
        if any(part in SKIP_DIRS for part in path.relative_to(root).parts[:-1]):
            continue
        if path.is_file() and (path.suffix in SUFFIXES or path.name == 'CMakeLists.txt'):
            found.append(path)
    return sorted(found)


def check_package(package_dir: Path) -> list[str]:
    """Return every problem with the package's copyright headers (empty when all are valid)."""
    license_file = package_dir / 'LICENSE'
    if not license_file.is_file():
        return [f'{package_dir}: no LICENSE file']
    notice = permission_notice(license_file)
    problems = [file_problem(p, notice) for p in source_files(package_dir)]
    return [p for p in problems if p]


def add_header(path: Path, notice: str) -> None:
    """Insert the header after any shebang or coding line."""
    text = path.read_text(encoding='utf-8')
    lines = text.split('\n')
    i = 0
    while i < len(lines) and (lines[i].startswith('#!') or 'coding' in lines[i][:30]):
        i += 1
    head = '\n'.join(lines[:i])
    rest = '\n'.join(lines[i:])
    path.write_text((head + '\n' if head else '') + header_comment(notice) + rest)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[1])
    ap.add_argument('packages', nargs='+', type=Path, help='package directories (with a LICENSE)')
    ap.add_argument('--fix', action='store_true', help='add the header to files that lack one')
    ap.add_argument(
        '--notice-from', type=Path, help='take the notice from this LICENSE (for non-packages)'
    )
    args = ap.parse_args(argv)
    problems = []
    for package in args.packages:
        license_file = args.notice_from or package / 'LICENSE'
        notice = permission_notice(license_file)
        for path in source_files(package):
            text = path.read_text(encoding='utf-8')
            if args.fix and text.strip() and not _copyright_lines(text)[1]:
                add_header(path, notice)
            problem = file_problem(path, notice)
            if problem:
                problems.append(problem)
    print('\n'.join(problems) if problems else 'copyright headers: all valid')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
