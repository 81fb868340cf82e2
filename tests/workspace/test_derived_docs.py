# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""The docs' reports derived from a shipped file were made from the file that ships now."""

from __future__ import annotations

import hashlib
import json
from pathlib import Path

from hexapod_navigation.core.repertoire import shipped_repertoire
from hexapod_navigation.core.specialists import shipped_specialists
from hexapod_navigation.core.step_bank import shipped_step_bank
import pytest

WS = Path(__file__).resolve().parents[2]
# what a navigation report's summary.json names by its digests, and where each ships
SHIPPED = {
    'repertoire': shipped_repertoire,
    'bank': shipped_step_bank,
    'specialists': shipped_specialists,
}
REPORTS = sorted((WS / 'docs' / 'navigation').rglob('summary.json'))


def test_the_docs_hold_navigation_reports():
    names = {p.parent.relative_to(WS).as_posix() for p in REPORTS}
    assert {'docs/navigation', 'docs/navigation/locked'} <= names


@pytest.mark.parametrize('report', REPORTS, ids=lambda p: p.parent.relative_to(WS).as_posix())
def test_a_navigation_report_walked_the_shipped_repertoire_bank_and_specialists(report: Path):
    # a map shipped since the report was written leaves it describing files no one has:
    # hexapod_adapt/maps/regenerate_derived.sh makes every report again
    summary = json.loads(report.read_text())
    digests = summary['inputs_sha256']
    assert set(digests) == set(SHIPPED)
    for name, digest in digests.items():
        shipped = SHIPPED[name]()
        assert hashlib.sha256(shipped.read_bytes()).hexdigest() == digest, (
            f'{report.relative_to(WS)} was made from another {name} than {shipped.name}:'
            ' run hexapod_adapt/maps/regenerate_derived.sh'
        )
