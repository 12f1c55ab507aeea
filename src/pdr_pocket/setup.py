from glob import glob

from setuptools import find_packages, setup

package_name = "pdr_pocket"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + package_name]),
        ("share/" + package_name, ["package.xml"]),
        ("share/" + package_name + "/config", glob("config/*.yaml") + glob("config/*.xml")),
        ("share/" + package_name + "/launch", glob("launch/*.launch.xml")),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="PDR stack maintainers",
    maintainer_email="maintainers@pdr-stack.org",
    description="See package.xml.",
    license="Apache-2.0",
    entry_points={"console_scripts": ["pdr-pocket = pdr_pocket.cli:main",
                                     "pocket_pdr = pdr_pocket.nodes.pocket_pdr:main",
                                     "stride_calibrator = "
                                     "pdr_pocket.nodes.stride_calibrator:main"]},
)
