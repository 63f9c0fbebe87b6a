"""ament_python build of linkage_ros: the pure `solver` library and the ROS 2 package `linkage_ros`.

Works with colcon (ROS 2 Jazzy or colcon from PyPI) and with plain pip.
"""

from glob import glob
from pathlib import Path

from setuptools import find_packages, setup

package_name = "linkage_ros"
here = Path(__file__).parent


def _files(pattern: str) -> list[str]:
    return sorted(p for p in glob(pattern, recursive=True) if Path(p).is_file())


def _tree(root: str) -> list[tuple[str, list[str]]]:
    """data_files entries that keep the folder layout of ``root`` under share/linkage_ros."""
    groups: dict[str, list[str]] = {}
    for path in _files(f"{root}/**/*"):
        groups.setdefault(str(Path(path).parent), []).append(path)
    return [(f"share/{package_name}/{folder}", paths) for folder, paths in sorted(groups.items())]


setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(include=["solver", "solver.*", "linkage_ros", "linkage_ros.*"]),
    data_files=[
        ("share/ament_index/resource_index/packages", [f"resource/{package_name}"]),
        (f"share/{package_name}", ["package.xml"]),
        (f"share/{package_name}/launch", _files("launch/*.launch.py")),
        *_tree("config"),
    ],
    python_requires=">=3.10",
    install_requires=["setuptools", "numpy>=1.26", "PyYAML>=6", "scipy>=1.11"],
    extras_require={
        # MCAP recording works with numpy 1.26 (ROS 2 Jazzy's); the rerun view needs numpy >= 2
        "record": ["rosbags>=0.10", "mcap>=1.2", "mcap-ros2-support>=0.5"],
        # the real ROS 2 Jazzy (rclpy with Fast DDS, the message packages) as wheels, for
        # mechanism_node outside a ROS install; rosbags serialises the node's messages
        "ros": ["ros-jazzy-rclpy[fastrtps]", "ros-jazzy-common-interfaces", "rosbags>=0.10"],
        "view": ["rerun-sdk>=0.41,<0.42"],
        "test": [
            "pytest>=8",
            "pytest-xdist>=3",
            "hypothesis>=6.100",
            "mpmath>=1.3",
            "ruff>=0.6",
            "mypy>=1.10",
            "types-PyYAML",
            "yourdfpy>=0.0.56",
            "pillow",
            "colcon-common-extensions",
            "distributed>=2024.1",
            # an engine from the field as the dynamics' oracle (tests/bench/test_dynamics_exudyn.py)
            "exudyn>=1.13",
            # robot model files (issue 31): MuJoCo's compiler reads MJCF, the 2F-85 reference
            "mujoco>=3",
        ],
        # importing MJCF and URDF models (solver.models, docs/models.md)
        "models": ["mujoco>=3", "yourdfpy>=0.0.56"],
        # dimensional synthesis on a Dask cluster (solver.synthesize(workers=...), linkage-synth --dask)
        "synth": ["distributed>=2024.1"],
        "bench": ["matplotlib>=3.8", "pylinkage==1.3.0", "numba>=0.60", "kinepy==0.1.7", "mujoco>=3", "exudyn>=1.13"],
    },
    zip_safe=True,
    maintainer="linkage_ros developers",
    maintainer_email="linkage-ros@example.com",
    description="Exact closed-form kinematics of linkage mechanisms, published into ROS 2.",
    license="Apache-2.0",
    entry_points={
        "console_scripts": [
            "linkage-solve = solver.cli:main",
            "linkage-synth = linkage_ros.synth_cli:main",
            "linkage-import = solver.structure_cli:import_main",
            "mechanism_node = linkage_ros.node:main",
            "linkage-run = linkage_ros.cli:run_main",
            "linkage-view = linkage_ros.cli:view_main",
            "linkage-mcap = linkage_ros.cli:mcap_main",
            "linkage-urdf = linkage_ros.urdf:main",
            "linkage-echo = linkage_ros.echo:main",
            "linkage-mjcf = solver.mjcf_cli:main",
        ],
    },
)
