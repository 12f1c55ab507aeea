from setuptools import find_packages, setup

package_name = "pdr_ros2"

setup(
    name=package_name,
    version="0.1.0",
    packages=find_packages(exclude=["test"]),
    data_files=[
        ("share/ament_index/resource_index/packages", ["resource/" + package_name]),
        ("share/" + package_name, ["package.xml"]),
        ("share/" + package_name + "/schema", ["schema/launch.xsd"]),
    ],
    install_requires=["setuptools"],
    zip_safe=True,
    maintainer="PDR stack maintainers",
    maintainer_email="maintainers@pdr-stack.org",
    description="See package.xml.",
    license="Apache-2.0",
    entry_points={"console_scripts": ["ros2 = pdr_ros2.command:main"]},
)
