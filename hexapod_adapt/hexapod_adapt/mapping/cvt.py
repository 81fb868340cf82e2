# Copyright 2026 Hexapod adaptation team
# SPDX-License-Identifier: MIT
"""
Centroidal Voronoi tessellation of the duty-factor space (thesis 4.2.1); ROS-free.

K-means (scikit-learn) on uniform random samples of [0, 1]^dim gives ``n`` centroids that
divide the space into niches of roughly equal volume. Seeded: the same (n, dim, samples, seed)
gives the same centroids. Computed centroids can be cached in the thesis's
``centroids_<n>_<dim>.dat`` text format so every map of a study shares one CVT.
"""

from __future__ import annotations

import os
from pathlib import Path

from hexapod_adapt.mapping.archive import load_centroids, save_centroids
import numpy as np


def compute_cvt(
    n_niches: int, dim: int = 6, samples: int | None = None, seed: int = 0, max_iter: int = 300
) -> np.ndarray:
    """
    (n_niches, dim) centroids.

    ``samples`` defaults to 25 per niche (the thesis used 375 per niche for 40 000 niches on a 624
    GB machine; more samples, more even niches).
    """
    from sklearn.cluster import KMeans

    if n_niches < 1:
        raise ValueError(f'n_niches must be >= 1, got {n_niches}')
    samples = samples if samples is not None else 25 * n_niches
    if samples < n_niches:
        raise ValueError(f'need at least as many samples ({samples}) as niches ({n_niches})')
    x = np.random.default_rng(seed).random((samples, dim))
    km = KMeans(
        n_clusters=n_niches, init='k-means++', n_init=1, max_iter=max_iter, random_state=seed
    )
    km.fit(x)
    return np.asarray(km.cluster_centers_, dtype=float)


def cvt_cache_path(directory: str | os.PathLike, n_niches: int, dim: int = 6) -> Path:
    """Where the centroids of ``n_niches`` niches are cached in ``directory``."""
    return Path(directory) / f'centroids_{n_niches}_{dim}.dat'


def cached_cvt(
    directory: str | os.PathLike,
    n_niches: int,
    dim: int = 6,
    samples: int | None = None,
    seed: int = 0,
) -> np.ndarray:
    """
    Load the centroids from ``directory``, or compute them and write them there.

    The file is ``centroids_<n>_<dim>.dat``; one of the wrong shape is recomputed.
    """
    path = cvt_cache_path(directory, n_niches, dim)
    if path.is_file():
        c = load_centroids(path, dim)
        if c.shape == (n_niches, dim):
            return c
        raise ValueError(
            f'{path} holds {c.shape[0]} centroids of dimension {c.shape[1]}, '
            f'expected {n_niches} x {dim}'
        )
    c = compute_cvt(n_niches, dim, samples, seed)
    save_centroids(path, c)
    return c
