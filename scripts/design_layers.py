#!/usr/bin/env python3
"""docs/DESIGN.md's layers block, generated from the rank table that scripts/check-layers.sh enforces (its
--describe), so the design describes the layers the test holds the code to.
Usage: /usr/bin/python3 scripts/design_layers.py [--check] DESIGN.md SRC_DIR
  (writes the block; --check writes nothing and exits 1 when the block is not what check-layers describes)"""
import pathlib
import subprocess
import sys

import readme_block


def main(argv):
    check = "--check" in argv
    args = [a for a in argv if a != "--check"]
    if len(args) != 2:
        raise SystemExit(__doc__)
    design, src = args
    script = pathlib.Path(__file__).resolve().parent / "check-layers.sh"
    body = subprocess.run(["bash", str(script), src, "--describe"], check=True, capture_output=True,
                          text=True).stdout
    if check:
        if not readme_block.is_current(design, "layers", body):
            print(f"{design}: its layers block is not what scripts/check-layers.sh enforces; run "
                  f"/usr/bin/python3 scripts/design_layers.py {design} {src}")
            return 1
        return 0
    readme_block.replace(design, "layers", body)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
