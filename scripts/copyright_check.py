# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Copyright headers: check them, or add the missing ones (``--fix``).

A source file passes when its first comment block (after a shebang or coding line) holds a
``Copyright <year> <holder>`` line and an ``SPDX-License-Identifier: <id>`` line whose id is the
package's licence (its ``package.xml`` ``<license>``; ``--license`` for folders that are not
packages). Two lines, so a module's first visible text is its docstring; the full licence text
is the package's LICENSE file. Every package test runs this check: ``ament_copyright``
recognises a licence only by its full file-header text, so it does not accept SPDX headers.

    python scripts/copyright_check.py hexapod_sim             # the files without a valid header
    python scripts/copyright_check.py --fix hexapod_*         # add it where it is missing
    python scripts/copyright_check.py --license MIT scripts   # a folder that is not a package
"""

from __future__ import annotations

import argparse
from pathlib import Path
import re
import sys
import xml.etree.ElementTree as ElementTree

HOLDER = 'Hexapod adaptation team'
YEAR = 2026
#: The source files that need a header, by suffix, plus CMakeLists.txt.
SUFFIXES = ('.py', '.cmake')
SKIP_DIRS = {'build', 'install', 'log', '__pycache__', '.venv', '.git', 'resource', 'out'}
COPYRIGHT_LINE = re.compile(r'^copyright(?:\s+\(c\))?\s+\d{4}(?:-\d{4})?,?\s+\S', re.IGNORECASE)
SPDX_LINE = re.compile(r'^SPDX-License-Identifier:\s*(\S.*?)\s*$')


def package_license(package_dir: Path) -> str:
    """Return the licence ``package.xml`` declares (ValueError if none, or more than one)."""
    manifest = package_dir / 'package.xml'
    if not manifest.is_file():
        raise ValueError(f'{package_dir}: no package.xml (pass --license for other folders)')
    licenses = [e.text.strip() for e in ElementTree.parse(manifest).getroot().iter('license')]
    if len(licenses) != 1:
        raise ValueError(f'{manifest}: expected one <license>, found {licenses}')
    return licenses[0]


def header_comment(license_id: str, holder: str = HOLDER, year: int = YEAR) -> str:
    """Return the header as '#' comment lines."""
    return f'# Copyright {year} {holder}\n# SPDX-License-Identifier: {license_id}\n'


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


def file_problem(path: Path, license_id: str) -> str | None:
    """Return what is wrong with ``path``'s copyright header, or None if it is valid."""
    text = path.read_text(encoding='utf-8')
    if not text.strip():
        return None  # an empty file (e.g. an empty __init__.py) has nothing to protect
    block = _first_comment_block(text)
    if not any(COPYRIGHT_LINE.match(line) for line in block):
        return f'{path}: no "Copyright <year> <holder>" line in the first comment block'
    ids = [m.group(1) for m in map(SPDX_LINE.match, block) if m]
    if not ids:
        return (
            f'{path}: no "SPDX-License-Identifier: {license_id}" line in the first comment block'
        )
    if ids[0] != license_id:
        return f'{path}: SPDX-License-Identifier {ids[0]}, but the licence is {license_id}'
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
    if not (package_dir / 'LICENSE').is_file():
        return [f'{package_dir}: no LICENSE file']
    license_id = package_license(package_dir)
    problems = [file_problem(p, license_id) for p in source_files(package_dir)]
    return [p for p in problems if p]


def add_header(path: Path, license_id: str) -> None:
    """Insert the header after any shebang or coding line."""
    lines = path.read_text(encoding='utf-8').split('\n')
    i = 0
    while i < len(lines) and (lines[i].startswith('#!') or 'coding' in lines[i][:30]):
        i += 1
    head = '\n'.join(lines[:i])
    rest = '\n'.join(lines[i:])
    path.write_text((head + '\n' if head else '') + header_comment(license_id) + rest)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[1])
    ap.add_argument('folders', nargs='+', type=Path, help='package directories, or others')
    ap.add_argument('--fix', action='store_true', help='add the header to files that lack one')
    ap.add_argument('--license', help='the SPDX id for folders that are not packages (e.g. MIT)')
    args = ap.parse_args(argv)
    problems = []
    for folder in args.folders:
        license_id = args.license or package_license(folder)
        for path in source_files(folder):
            if args.fix and file_problem(path, license_id) and path.read_text().strip():
                block = _first_comment_block(path.read_text(encoding='utf-8'))
                if not any(COPYRIGHT_LINE.match(line) for line in block):
                    add_header(path, license_id)
            problem = file_problem(path, license_id)
            if problem:
                problems.append(problem)
    print('\n'.join(problems) if problems else 'copyright headers: all valid')
    return 1 if problems else 0


if __name__ == '__main__':
    sys.exit(main())
