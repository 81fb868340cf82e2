# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""M-BOA: GP posterior, UCB with the standard deviation, stopping, tested gaits, noise."""

from dataclasses import replace

from hexapod_adapt.online.mboa import matern52, Mboa, MboaConfig
import numpy as np
import pytest


def _map(m=300, seed=0):
    rng = np.random.default_rng(seed)
    return rng.random((m, 6)), rng.uniform(0.05, 0.45, m)


def test_posterior_matches_a_direct_gp_computation():
    x, prior = _map(60)
    cfg = MboaConfig(noise=0.001, length_scale=0.4)
    opt = Mboa(x, prior, cfg)
    obs = {3: 0.1, 17: 0.3, 40: -0.05}
    for i, y in obs.items():
        opt.observe(i, y)
    idx = np.array(list(obs))
    k = matern52(x[idx], x[idx], 0.4) + 0.001 * np.eye(3)
    ks = matern52(x, x[idx], 0.4)
    mu = prior + ks @ np.linalg.solve(k, np.array(list(obs.values())) - prior[idx])
    var = 1.0 - np.einsum('ij,ji->i', ks, np.linalg.solve(k, ks.T))
    np.testing.assert_allclose(opt.mean, mu, atol=1e-10)
    np.testing.assert_allclose(opt.std**2, var, atol=1e-10)


def test_noise_is_the_configured_variance_not_a_library_default():
    x, prior = _map(10)
    opt = Mboa(x, prior, MboaConfig(noise=0.001))
    opt.observe(0, prior[0] + 1.0)
    # posterior mean at the observed point moves by 1 / (1 + noise) of the surprise
    assert opt.mean[0] - prior[0] == pytest.approx(1.0 / 1.001, rel=1e-9)
    assert opt.std[0] ** 2 == pytest.approx(1.0 - 1.0 / 1.001, rel=1e-6)


def test_ucb_adds_kappa_times_standard_deviation():
    # find a seeded situation where kappa*sigma and kappa*sigma^2 pick different gaits, and
    # check the optimiser picks the sigma one (a trap in existing IT&E code)
    for seed in range(100):
        x, prior = _map(80, seed=seed)
        opt = Mboa(x, prior, MboaConfig(kappa=0.3, exclude_tested=False))
        for i in (0, 1, 2):
            opt.observe(i, prior[i] - 0.2)
        with_std = int(np.argmax(opt.mean + 0.3 * opt.std))
        with_var = int(np.argmax(opt.mean + 0.3 * opt.std**2))
        if with_std != with_var:
            assert opt.next_index() == with_std
            return
    pytest.fail('no seed separated sigma from sigma^2')


def test_stops_at_alpha_of_best_prediction_and_never_exceeds_max_trials():
    x, prior = _map(200, seed=4)
    opt = Mboa(x, prior, MboaConfig(max_trials=5, alpha=0.9))
    while not opt.should_stop()[0]:
        i = opt.next_index()
        opt.observe(i, 0.3 * prior[i])  # the robot is much worse than the map
    assert len(opt.trials) == 5 and opt.should_stop()[1].startswith('budget used: 5 trials')
    with pytest.raises(RuntimeError):
        opt.observe(0, 0.1)
    good = Mboa(x, prior, MboaConfig(max_trials=20, alpha=0.9))
    i = good.next_index()
    good.observe(i, prior[i])  # reality as predicted: stop after one trial
    stop, why = good.should_stop()
    assert stop and 'alpha' in why and len(good.trials) == 1


def test_tested_gaits_are_not_offered_again_by_default():
    x, prior = _map(30, seed=2)
    opt = Mboa(x, prior, MboaConfig(max_trials=30, alpha=1.0))
    seen = []
    for _ in range(30):
        if opt.should_stop()[0]:
            break
        i = opt.next_index()
        seen.append(i)
        opt.observe(i, 0.0)
    assert len(seen) == len(set(seen)) == 30
    assert opt.should_stop() == (True, 'budget used: 30 trials; best measured 0.000 m/s')


def test_bad_configuration_and_observations_are_refused():
    with pytest.raises(ValueError, match='alpha'):
        MboaConfig(alpha=1.5)
    with pytest.raises(ValueError, match='noise'):
        MboaConfig(noise=0.0)
    x, prior = _map(5)
    opt = Mboa(x, prior)
    with pytest.raises(ValueError, match='does not exist'):
        opt.observe(5, 0.1)
    with pytest.raises(ValueError, match='finite'):
        opt.observe(0, float('nan'))
    with pytest.raises(ValueError, match='one prior speed'):
        Mboa(x, prior[:3])


def test_incremental_posterior_equals_a_full_refit():
    """
    The step updates the GP one trial at a time.

    The numbers are those of the textbook posterior (Matern 5/2, explicit noise) computed from
    scratch.
    """
    from hexapod_adapt.online.mboa import matern52

    rng = np.random.default_rng(3)
    d, prior = rng.random((3000, 6)), rng.uniform(0.0, 0.4, 3000)
    cfg = MboaConfig(max_trials=15, noise=0.002, length_scale=0.3)
    opt = Mboa(d, prior, cfg)
    for _ in range(15):
        opt.observe(opt.next_index(), float(rng.uniform(-0.1, 0.4)))
        idx = np.array([t.index for t in opt.trials])
        y = np.array([t.measured for t in opt.trials])
        k = matern52(d[idx], d[idx], cfg.length_scale) + cfg.noise * np.eye(len(idx))
        ks = matern52(d, d[idx], cfg.length_scale)
        mean = prior + ks @ np.linalg.solve(k, y - prior[idx])
        var = 1.0 - np.einsum('ij,ji->i', ks, np.linalg.solve(k, ks.T))
        np.testing.assert_allclose(opt.mean, mean, atol=1e-12)
        np.testing.assert_allclose(opt.std, np.sqrt(np.maximum(var, 0.0)), atol=1e-7)


def test_signal_variance_scales_the_uncertainty_not_the_mean():
    """Kernel and noise variance scaled together: the same posterior mean, std scaled by root."""
    rng = np.random.default_rng(3)
    x, prior = rng.random((40, 6)), rng.random(40) * 0.4
    a = Mboa(x, prior, MboaConfig(noise=0.001, signal_variance=1.0))
    b = Mboa(x, prior, MboaConfig(noise=0.00001, signal_variance=0.01))
    for index, speed in [(3, 0.1), (17, 0.25), (30, 0.05)]:
        a.observe(index, speed)
        b.observe(index, speed)
    np.testing.assert_allclose(a.mean, b.mean, atol=1e-10)
    np.testing.assert_allclose(b.std, a.std * 0.1, atol=1e-10)
    assert 0.099 < np.max(b.std) <= 0.1  # the least correlated untried gait: nearly the prior


def test_expected_gain_is_the_expected_improvement_over_the_best():
    rng = np.random.default_rng(4)
    x, prior = rng.random((30, 6)) * 3, rng.random(30) * 0.4
    opt = Mboa(x, prior, MboaConfig(signal_variance=0.01, length_scale=0.3))
    opt.observe(int(np.argmax(prior)), 0.2)
    gain = opt.expected_gain()
    assert gain[int(np.argmax(prior))] == 0.0  # tried
    i = int(np.argmax(gain))
    draws = opt.mean[i] + opt.std[i] * rng.standard_normal(400_000)
    assert gain[i] == pytest.approx(np.mean(np.maximum(draws - 0.2, 0.0)), rel=0.02)
    assert opt.max_expected_gain() == gain[i]


def test_stop_gain_goes_on_while_a_trial_is_worth_walking():
    x = np.array([[0.0] * 6, [0.05] * 6, [3.0] * 6])
    prior = np.array([0.40, 0.39, 0.30])
    thesis = Mboa(x, prior, MboaConfig(alpha=0.5))
    thesis.observe(0, 0.25)  # 0.25 >= 0.5 x 0.39: the thesis rule stops
    assert thesis.stop_reason().value == 'alpha_reached'
    going = Mboa(x, prior, MboaConfig(alpha=0.5, signal_variance=0.01, stop_gain=0.01))
    going.observe(0, 0.25)  # the far gait (0.30 predicted, +/-0.1) may still gain > 0.01
    assert going.max_expected_gain() > 0.01
    assert going.stop_reason().value == 'continue'
    going.observe(going.next_index(), 0.31)
    going.observe(going.next_index(), 0.2)
    assert going.stop_reason().value == 'alpha_reached'
    assert going.max_expected_gain() < 0.01


def test_the_thesis_profile_is_thesis_5_2_2_and_settings_override_a_profile():
    from hexapod_adapt.online.mboa import profile, PROFILES
    from hexapod_adapt.online.run_config import run_settings

    thesis = PROFILES['thesis']
    assert (thesis.alpha, thesis.kappa, thesis.length_scale, thesis.noise) == (
        0.9,
        0.05,
        0.4,
        0.001,
    )
    assert thesis.signal_variance == 1.0 and thesis.stop_gain is None
    base = {'max_trials': 24, 'trial_duration': 5.0, 'alpha': 0.0, 'kappa': 0.0}
    base.update({'length_scale': 0.0, 'noise': 0.0})
    config, duration = run_settings({**base, 'profile': 'thesis'})
    assert config == replace(thesis, max_trials=24) and duration == 5.0
    config, _ = run_settings({**base, 'profile': '', 'alpha': 0.5})  # '' = the default profile
    assert config == replace(PROFILES['default'], max_trials=24, alpha=0.5)
    with pytest.raises(ValueError, match="unknown M-BOA profile 'fast'"):
        profile('fast')
    with pytest.raises(ValueError, match='alpha'):
        run_settings({**base, 'profile': 'thesis', 'alpha': 1.5})
    # the expected-gain stop: 0 is not given (the profile's), a value replaces it, and only
    # no_gain_stop turns it off
    default = PROFILES['default'].stop_gain
    assert default > 0 and run_settings(base)[0].stop_gain == default
    assert run_settings({**base, 'stop_gain': 0.01})[0].stop_gain == 0.01
    assert run_settings({**base, 'no_gain_stop': True})[0].stop_gain is None
    assert run_settings({**base, 'stop_gain': 0.01, 'no_gain_stop': True})[0].stop_gain is None
    for bad in (2.0, -1.0, float('nan'), float('-inf')):
        with pytest.raises(ValueError, match='stop_gain'):
            run_settings({**base, 'stop_gain': bad})


def test_one_hypothesis_is_the_thesis_gp_bit_for_bit():
    x, prior = _map(80)
    plain, empty = Mboa(x, prior), Mboa(x, prior, hypotheses=np.zeros((0, 80)))
    for i, y in ((5, 0.2), (9, 0.05), (30, 0.4)):
        plain.observe(i, y)
        empty.observe(i, y)
    np.testing.assert_array_equal(plain.mean, empty.mean)
    np.testing.assert_array_equal(plain.std, empty.std)
    assert empty.weights.tolist() == [1.0]


def test_hypotheses_are_weighed_by_marginal_likelihood_and_mixed():
    x, prior = _map(60, seed=3)
    rng = np.random.default_rng(4)
    other = prior - rng.uniform(0.0, 0.3, 60)
    cfg = MboaConfig(signal_variance=0.01, length_scale=0.2)
    opt = Mboa(x, prior, cfg, hypotheses=other[None, :])
    np.testing.assert_allclose(opt.weights, [0.5, 0.5])
    np.testing.assert_allclose(opt.mean, (prior + other) / 2)  # before any trial
    obs = {2: other[2], 11: other[11], 25: other[25]}  # the trials agree with the other one
    for i, y in obs.items():
        opt.observe(i, y)
    # direct computation: one GP per hypothesis, weighted by its marginal likelihood
    idx = np.array(list(obs))
    y = np.array(list(obs.values()))
    k = 0.01 * matern52(x[idx], x[idx], 0.2) + 0.001 * np.eye(3)
    ks = 0.01 * matern52(x, x[idx], 0.2)
    means, lik = [], []
    for m in (prior, other):
        r = y - m[idx]
        means.append(m + ks @ np.linalg.solve(k, r))
        lik.append(np.exp(-0.5 * r @ np.linalg.solve(k, r)))
    w = np.array(lik) / sum(lik)
    mean = w @ np.array(means)
    var = 0.01 - np.einsum('ij,ji->i', ks, np.linalg.solve(k, ks.T))
    var = var + w @ (np.array(means) - mean) ** 2
    np.testing.assert_allclose(opt.weights, w, atol=1e-10)
    assert opt.weights[1] > opt.weights[0]
    np.testing.assert_allclose(opt.mean, mean, atol=1e-10)
    np.testing.assert_allclose(opt.std**2, var, atol=1e-10)


def test_a_bank_hypothesis_that_explains_the_damage_finds_its_best_gait():
    x, prior = _map(400, seed=5)
    rng = np.random.default_rng(6)
    damaged = np.clip(prior - rng.uniform(0.0, 0.4, 400), -0.05, None)  # the robot's truth
    decoys = [np.clip(prior - rng.uniform(0.0, 0.4, 400), -0.05, None) for _ in range(5)]
    cfg = replace(MboaConfig(), signal_variance=0.01, length_scale=0.2, alpha=0.95, kappa=0.5)
    opt = Mboa(x, prior, cfg, hypotheses=np.array([*decoys, damaged]))
    while not opt.should_stop()[0]:
        i = opt.next_index()
        opt.observe(i, damaged[i])
    assert int(np.argmax(opt.weights)) == 6  # the true damage's hypothesis
    assert opt.best().measured >= 0.95 * damaged.max()
    blind = Mboa(x, prior, cfg)
    while not blind.should_stop()[0]:
        i = blind.next_index()
        blind.observe(i, damaged[i])
    assert len(opt.trials) <= len(blind.trials)


def test_malformed_hypotheses_are_refused():
    x, prior = _map(10)
    with pytest.raises(ValueError, match='one speed per descriptor'):
        Mboa(x, prior, hypotheses=np.zeros((2, 9)))
    with pytest.raises(ValueError, match='finite'):
        Mboa(x, prior, hypotheses=np.full((1, 10), np.nan))


def test_known_models_get_a_tight_gp_and_unknown_damage_the_profile_kernel():
    x, prior = _map(60, seed=7)
    rng = np.random.default_rng(8)
    other = prior - rng.uniform(0.0, 0.3, 60)
    cfg = MboaConfig(signal_variance=0.01, length_scale=0.2, known_std=0.03, prior_unknown=0.2)
    opt = Mboa(x, prior, cfg, hypotheses=other[None, :])
    # the map, the bank's one, then 'unknown damage' (the map under the profile's kernel)
    np.testing.assert_allclose(opt.weights, [0.4, 0.4, 0.2])
    truth = other + rng.normal(0.0, 0.01, 60)
    obs = {2: truth[2], 11: truth[11], 25: truth[25], 40: truth[40]}
    for i, y in obs.items():
        opt.observe(i, y)
    # direct: each hypothesis's Gaussian likelihood under its own kernel, determinant included
    idx = np.array(list(obs))
    y = np.array(list(obs.values()))
    means, var, lik = [], [], []
    for m, s2, prior_w in ((prior, 0.03**2, 0.4), (other, 0.03**2, 0.4), (prior, 0.01, 0.2)):
        k = s2 * matern52(x[idx], x[idx], 0.2) + 0.001 * np.eye(4)
        ks = s2 * matern52(x, x[idx], 0.2)
        r = y - m[idx]
        means.append(m + ks @ np.linalg.solve(k, r))
        var.append(s2 - np.einsum('ij,ji->i', ks, np.linalg.solve(k, ks.T)))
        lik.append(prior_w * np.exp(-0.5 * r @ np.linalg.solve(k, r)) / np.sqrt(np.linalg.det(k)))
    w = np.array(lik) / sum(lik)
    mean = w @ np.array(means)
    np.testing.assert_allclose(opt.weights, w, atol=1e-10)
    np.testing.assert_allclose(opt.mean, mean, atol=1e-10)
    np.testing.assert_allclose(
        opt.std**2, w @ np.array(var) + w @ (np.array(means) - mean) ** 2, atol=1e-10
    )
    assert opt.weights[1] > 0.9  # the bank's model of this damage
    # damage no model describes: 'unknown damage' takes over
    odd = Mboa(x, prior, cfg, hypotheses=other[None, :])
    strange = prior * rng.uniform(-0.5, 1.5, 60)
    for i in (2, 11, 25, 40, 50):
        odd.observe(i, strange[i])
    assert int(np.argmax(odd.weights)) == 2 and odd.weights[2] > 0.9
    # without hypotheses known_std changes nothing: the thesis's GP
    alone, plain = Mboa(x, prior, cfg), Mboa(x, prior, replace(cfg, known_std=0.0))
    for o in (alone, plain):
        o.observe(3, 0.1)
    np.testing.assert_array_equal(alone.mean, plain.mean)
    with pytest.raises(ValueError, match='known_std'):
        MboaConfig(known_std=-0.1)


def test_the_shared_offset_is_a_constant_kernel_term_that_slows_untried_gaits():
    rng = np.random.default_rng(7)
    x, prior = rng.random((50, 6)), rng.uniform(0.2, 0.4, 50)
    cfg = MboaConfig(noise=0.001, length_scale=0.3, signal_variance=0.01, offset_std=0.1)
    opt = Mboa(x, prior, cfg)
    obs = {2: prior[2] - 0.2, 11: prior[11] - 0.15, 29: prior[29] - 0.25}
    for i, y in obs.items():
        opt.observe(i, y)
    idx = np.array(list(obs))
    kern = 0.01 * matern52(x, x[idx], 0.3) + 0.01  # the offset's variance 0.1^2 everywhere
    k = kern[idx] + 0.001 * np.eye(3)
    mu = prior + kern @ np.linalg.solve(k, np.array(list(obs.values())) - prior[idx])
    var = 0.02 - np.einsum('ij,ji->i', kern, np.linalg.solve(k, kern.T))
    np.testing.assert_allclose(opt.mean, mu, atol=1e-10)
    np.testing.assert_allclose(opt.std**2, var, atol=1e-10)
    # every gait, however far from the trials, is predicted slower than the map
    without = Mboa(x, prior, replace(cfg, offset_std=0.0))
    for i, y in obs.items():
        without.observe(i, y)
    far = int(np.argmin(matern52(x, x[idx], 0.3).max(axis=1)))
    assert opt.mean[far] < prior[far] - 0.1
    assert abs(without.mean[far] - prior[far]) < abs(opt.mean[far] - prior[far])
    with pytest.raises(ValueError, match='offset_std'):
        MboaConfig(offset_std=-0.1)
