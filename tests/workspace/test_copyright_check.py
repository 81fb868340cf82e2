# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The copyright check every package's lint test runs (scripts/copyright_check.py)."""

from __future__ import annotations

import importlib.util
from pathlib import Path
import subprocess
import sys

import pytest

WS = Path(__file__).resolve().parents[2]
CHECK = WS / 'scripts' / 'copyright_check.py'
pytestmark = [pytest.mark.linter, pytest.mark.copyright]


def _check():
    spec = importlib.util.spec_from_file_location('copyright_check', CHECK)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _package(tmp_path: Path, license_id: str = 'MIT') -> Path:
    pkg = tmp_path / 'pkg'
    pkg.mkdir()
    (pkg / 'LICENSE').write_text('MIT License\n')
    (pkg / 'package.xml').write_text(
        f'<package format="3"><name>pkg</name><license>{license_id}</license></package>'
    )
    return pkg


def test_the_two_line_header_passes_and_every_other_is_named(tmp_path):
    check = _check()
    pkg = _package(tmp_path)
    (pkg / 'good.py').write_text(
        '#!/usr/bin/env python3\n# Copyright 2026 Team\n'
        '# SPDX-License-Identifier: MIT\n"""Doc."""\n'
    )
    (pkg / 'no_spdx.py').write_text('# Copyright 2026 Team\n"""Doc."""\n')
    (pkg / 'no_copyright.py').write_text('# SPDX-License-Identifier: MIT\n"""Doc."""\n')
    (pkg / 'other_licence.py').write_text(
        '# Copyright 2026 Team\n# SPDX-License-Identifier: GPL-3.0-only\n'
    )
    (pkg / 'empty.py').write_text('')
    problems = check.check_package(pkg)
    assert len(problems) == 3
    assert any('no_spdx.py: no "SPDX-License-Identifier: MIT"' in p for p in problems)
    assert any('no_copyright.py: no "Copyright' in p for p in problems)
    assert any('other_licence.py: SPDX-License-Identifier GPL-3.0-only' in p for p in problems)


def test_fix_adds_the_header_after_a_shebang_and_the_licence_comes_from_package_xml(tmp_path):
    pkg = _package(tmp_path, 'Apache-2.0')
    script = pkg / 'tool.py'
    script.write_text('#!/usr/bin/env python3\n"""Doc."""\n')
    r = subprocess.run(
        [sys.executable, str(CHECK), '--fix', str(pkg)], capture_output=True, text=True
    )
    assert r.returncode == 0, r.stdout
    assert script.read_text().splitlines()[:3] == [
        '#!/usr/bin/env python3',
        '# Copyright 2026 Hexapod adaptation team',
        '# SPDX-License-Identifier: Apache-2.0',
    ]


def test_the_workspace_folders_that_are_not_packages_carry_the_header():
    r = subprocess.run(
        [sys.executable, str(CHECK), '--license', 'MIT', 'scripts', 'tests', 'studies'],
        cwd=WS, capture_output=True, text=True,
    )  # fmt: skip
    assert r.returncode == 0, r.stdout
