#!/usr/bin/python3
"""The usage block of docs/USAGE.md (or any Markdown file holding one), generated from the CLI's own --help.

    scripts/readme-usage.py BIN README.md           rewrites the block between the usage markers
    scripts/readme-usage.py --check BIN README.md   exits 1 (and prints a diff) when the block differs

One synopsis per subcommand, in the order `partslam --help` lists them: the positionals, then every option as
--help shows it: required ones bare, the others in brackets with their default (`[--top 10]`) or, without one, their
value's type (`[--json TEXT]`); flags bare in brackets. The block is therefore exactly as true as --help (the ctest
`readme.usage` runs --check: a default or an option changed without `make readme-usage` fails it).
"""
import difflib
import re
import subprocess
import sys

BEGIN = "<!-- usage:begin: generated from `partslam CMD --help` by `make readme-usage`; do not edit -->"
END = "<!-- usage:end -->"
WIDTH = 116


def help_text(binary, *args):
    run = subprocess.run([binary, *args, "--help"], capture_output=True, text=True, check=False)
    if run.returncode != 0:
        sys.exit(f"readme-usage: '{binary} {' '.join(args)} --help' failed ({run.returncode}): {run.stderr}")
    return run.stdout


COLUMN = 30  # CLI11's option column: a spec shorter than this is padded to it, a longer one ends its line


def sections(text):
    """{section title: [entry lines]}: the lines under 'Positionals:', 'Options:', 'Subcommands:' that start an
    entry (two spaces, then a non-space), without their wrapped continuations."""
    out, current = {}, None
    for line in text.splitlines():
        title = re.match(r"^([A-Za-z][A-Za-z ]*):\s*$", line)
        if title:
            current = out.setdefault(title.group(1), [])
        elif current is not None and re.match(r"^  \S", line):
            current.append(line.rstrip())
        elif line.strip() == "":
            current = None
    return out


def subcommands(binary):
    names = [entry.split()[0] for entry in sections(help_text(binary)).get("Subcommands", [])]
    if not names:
        sys.exit("readme-usage: 'partslam --help' lists no subcommands")
    return names


def spec_of(entry):
    """The option's column (names, type, =default, REQUIRED, Excludes: ...), without the description."""
    if len(entry) > COLUMN and entry[COLUMN - 1] == " ":
        return entry[:COLUMN].strip()
    return entry.strip()


def option_word(spec):
    """'--top INT=10' -> ('--top', '10' or the type, required); a flag has no value."""
    names, _, rest = spec.partition(" ")
    rest = re.sub(r"\s*\b(Excludes|Needs):.*$", "", rest)
    required = " REQUIRED" in " " + rest
    rest = rest.replace("REQUIRED", "").strip()
    name = next((n for n in names.split(",") if n.startswith("--")), names.split(",")[0])
    if not rest:
        return name, None, required
    many = rest.endswith("...")
    rest = rest.removesuffix("...").strip()
    kind = re.split(r"[:=]", rest, maxsplit=1)[0]
    value = rest.rsplit("=", 1)[1] if "=" in rest else kind
    value = value.strip("[]").replace(" ", "")
    if many and "=" not in rest:
        value += ",..."
    return name, value, required


def synopsis(binary, command):
    parts = sections(help_text(binary, command))
    words = []
    positional_names = []
    for entry in parts.get("Positionals", []):
        spec = spec_of(entry).split()
        positional_names.append(spec[0])
        word = spec[0].upper()
        words.append(word if "REQUIRED" in spec else f"[{word}]")
    for entry in parts.get("Options", []):
        spec = spec_of(entry)
        if spec.split()[0] in positional_names or "--help" in spec.split()[0].split(","):
            continue
        name, value, required = option_word(spec)
        word = name if value is None else f"{name} {value}"
        words.append(word if required else f"[{word}]")
    lines, line = [], f"partslam {command}"
    indent = " " * (len("partslam ") + len(command) + 1)
    for word in words:
        if len(line) + 1 + len(word) > WIDTH and line.strip():
            lines.append(line)
            line = indent + word
        else:
            line += " " + word
    lines.append(line)
    return lines


def block(binary):
    lines = [BEGIN, "```sh"]
    for command in subcommands(binary):
        lines += synopsis(binary, command)
    lines += ["```", END]
    return "\n".join(lines)


def main(argv):
    check = "--check" in argv
    args = [a for a in argv if a != "--check"]
    if len(args) != 2:
        sys.exit(__doc__)
    binary, readme = args
    text = open(readme, encoding="utf-8").read()
    start, stop = text.find(BEGIN), text.find(END)
    if start < 0 or stop < start:
        sys.exit(f"readme-usage: {readme} has no usage block ({BEGIN} ... {END})")
    current = text[start:stop + len(END)]
    wanted = block(binary)
    if check:
        if current != wanted:
            sys.stdout.writelines(difflib.unified_diff((current + "\n").splitlines(True), (wanted + "\n").splitlines(True),
                                                       f"{readme} (usage block)", "partslam CMD --help"))
            print(f"\nreadme-usage: {readme}'s usage block disagrees with --help: run 'make readme-usage'")
            return 1
        return 0
    if current != wanted:
        with open(readme, "w", encoding="utf-8") as out:
            out.write(text[:start] + wanted + text[stop + len(END):])
        print(f"readme-usage: {readme}'s usage block rewritten from --help")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
