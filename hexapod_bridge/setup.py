from glob import glob

from setuptools import find_packages, setup

package_name = "hexapod_bridge"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{package_name}"]),
        (f"share/{package_name}", ["package.xml"]),
        (f"share/{package_name}/launch", glob("launch/*.py")),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="Hexapod adaptation team",
    maintainer_email="hexapod-dev@example.com",
    description="Serial bridge to the real hexapod (433 MHz radio link and Xsens IMU), protocol library and robot emulator.",
    license="MIT",
    entry_points={"console_scripts": ["bridge_node = hexapod_bridge.bridge_node:main", "robot_emulator = hexapod_bridge.emulator.cli:main"]},
)
