# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""Every study's command says what it does on --help, and runs nothing."""

from __future__ import annotations

import importlib
from pathlib import Path
import sys

import pytest

WS = Path(__file__).resolve().parents[2]
STUDIES = sorted(
    '.'.join(path.relative_to(WS).with_suffix('').parts)
    for path in (WS / 'studies').rglob('*.py')
    if '\ndef main(' in path.read_text()
)


def test_the_studies_have_commands_to_check():
    assert 'studies.diagnosis.noise_scales' in STUDIES and len(STUDIES) >= 30


@pytest.mark.parametrize('module', STUDIES)
def test_every_study_answers_help_without_running(module, monkeypatch, capsys):
    monkeypatch.syspath_prepend(str(WS))  # studies run as `python -m studies...` from the root
    monkeypatch.setattr(sys, 'argv', [module, '--help'])
    main = importlib.import_module(module).main
    with pytest.raises(SystemExit) as stop:
        main()
    assert stop.value.code == 0
    assert capsys.readouterr().out.startswith('usage: ')
