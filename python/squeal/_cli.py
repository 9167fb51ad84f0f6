"""The `squeal` command installed with the package: the Rust command line itself."""

import sys

from . import _squeal


def main() -> None:
    """Runs `squeal ARGS...` and exits with its status."""
    sys.exit(_squeal.cli(["squeal", *sys.argv[1:]]))


if __name__ == "__main__":
    main()
