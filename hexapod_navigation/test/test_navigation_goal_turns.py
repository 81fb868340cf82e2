# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""GoalTurns: only the newest goal walks, one at a time; waiting never blocks the others."""

from __future__ import annotations

import threading
import time

from hexapod_navigation.ros.goal_turns import GoalTurns


def _never() -> bool:
    return False


def test_the_newest_goal_gets_the_turn_and_older_ones_end_unwalked():
    turns = GoalTurns()
    turns.accepted('a')
    turns.accepted('b')
    assert not turns.wait_turn('a', _never)  # superseded before its turn
    assert turns.wait_turn('b', _never)
    assert turns.walking and not turns.superseded('b')
    turns.accepted('c')
    assert turns.superseded('b')  # the walking goal sees it at its next check
    turns.done('b')
    assert not turns.walking and turns.wait_turn('c', _never)


def test_a_waiting_goal_wakes_when_superseded_or_cancelled():
    turns = GoalTurns()
    turns.accepted('walking')
    assert turns.wait_turn('walking', _never)
    turns.accepted('waiting')
    answers: list[bool] = []
    waiter = threading.Thread(target=lambda: answers.append(turns.wait_turn('waiting', _never)))
    waiter.start()
    time.sleep(0.1)
    assert waiter.is_alive()  # waits while another goal walks
    turns.accepted('newer')
    waiter.join(1.0)
    assert answers == [False]
    cancelled = threading.Event()
    waiter = threading.Thread(
        target=lambda: answers.append(turns.wait_turn('newer', cancelled.is_set))
    )
    waiter.start()
    cancelled.set()
    waiter.join(1.0)
    assert answers == [False, False]


def test_a_goal_walks_only_after_it_was_the_newest_for_the_settle_time():
    turns = GoalTurns(settle_s=0.3)
    turns.accepted('a')
    t0 = time.monotonic()
    assert turns.wait_turn('a', _never)
    assert time.monotonic() - t0 >= 0.29


def test_close_stops_waiting_goals_and_waits_for_the_walking_one():
    turns = GoalTurns()
    turns.accepted('a')
    assert turns.wait_turn('a', _never)
    assert not turns.close(timeout_s=0.1)  # 'a' still walks
    assert turns.superseded('a')
    threading.Timer(0.1, lambda: turns.done('a')).start()
    assert turns.close(timeout_s=2.0)
    turns.accepted('b')
    assert not turns.wait_turn('b', _never)  # nothing walks once closing
