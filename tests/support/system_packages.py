"""The Debian packages some tests use as real, independent parts: ROS's own tf2, a real
browser, a real terminal, systemd's verifier, openssl's certificates, a network namespace.
A contributor's clone without one: its tests skip, naming the package to install (the
README's install line has them all); the project's CI installs them (.ci/run) and sets
``FACING_TEST_REQUIRE_SYSTEM_PACKAGES=1``, so that there a missing one fails (a
fresh machine failed the README's test command with "chromium is not installed")."""

from __future__ import annotations

import os
import shutil
import subprocess

import pytest

REQUIRE_SYSTEM_PACKAGES = "FACING_TEST_REQUIRE_SYSTEM_PACKAGES"

#: Each package, and what the tests use it for.
PACKAGES = {
    "openssl": "the secure example's certificate recipe",
    "python3-tf2": "ROS's own tf2 BufferCore, the TF buffer's oracle",
    "systemd": "systemd-analyze, the verifier of deploy/systemd's units",
    "chromium": "the live page, seen in a real browser",
    "tmux": "the terminal views, seen in a real terminal",
    "iproute2": "a network namespace, for the lossy link's test",
    "nftables": "its packet loss where the kernel has no netem",
}


def present(package: str) -> bool:
    """Whether ``package``'s part is here (a command on the PATH, or tf2 on the system
    Python)."""
    if package == "python3-tf2":
        return (
            bool(shutil.which("/usr/bin/python3"))
            and not subprocess.run(
                ["/usr/bin/python3", "-c", "import tf2_py"], capture_output=True, check=False
            ).returncode
        )
    command = {"systemd": "systemd-analyze", "iproute2": "ip", "nftables": "nft"}
    if package == "chromium":
        return browser() is not None
    return shutil.which(command.get(package, package)) is not None


def browser() -> str | None:
    return shutil.which("chromium") or shutil.which("chromium-browser")


def require(package: str) -> None:
    """Skip the calling test where ``package`` is missing (saying which, and why), fail it
    in the project's CI."""
    if present(package):
        return
    said = f"needs Debian's {package} ({PACKAGES[package]}): apt-get install {package}"
    if os.environ.get(REQUIRE_SYSTEM_PACKAGES, "") == "1":
        pytest.fail(f"{said}; CI runs every test, and .ci/run installs it")
    pytest.skip(said)
