from glob import glob

from setuptools import find_packages, setup

package_name = "hexapod_adapt"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{package_name}"]),
        (f"share/{package_name}", ["package.xml"]),
        (f"share/{package_name}/launch", glob("launch/*.py")),
        (f"share/{package_name}/maps", glob("maps/*.npz")),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="Hexapod adaptation team",
    maintainer_email="hexapod-dev@example.com",
    description="MAP-Elites map generation and map-based Bayesian optimisation (M-BOA) adaptation for the hexapod.",
    license="MIT",
    entry_points={"console_scripts": ["generate_map = hexapod_adapt.generate_cli:main",
                                      "adapt_node = hexapod_adapt.adapt_node:main",
                                      "adapt_client = hexapod_adapt.adapt_client:main",
                                      "run_experiment = hexapod_adapt.experiment_cli:main",
                                      "recover_recording = hexapod_adapt.recover_cli:main",
                                      "plot_map = hexapod_adapt.plot_map_cli:main"]},
)
