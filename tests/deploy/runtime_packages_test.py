#!/usr/bin/env python3
"""The container image cannot silently miss a library: docker/runtime-packages.txt, the runtime
stage's package list, must provide every shared library that oer-server and oer load.

Without a container engine: the real oer-server is started and its memory map read once it is
ready (/readyz 200: the GL renderer has started), so the libraries the EGL loader opens at run
time (Mesa's EGL vendor, the llvmpipe driver, LLVM) count as well as the linked ones; for the
command line, ldd's list. Each library's file is mapped to its Debian package (dpkg -S), and
that package must be in the closure of the list under Depends and Pre-Depends (virtual packages
through Provides, alternatives by apt's choice, the first one) or in the base image, a
`debootstrap --variant=minbase` system (the packages of priority required). Every listed
package must also be installed here, so that the closure is known.

    runtime_packages_test.py --server BIN --cli BIN --packages FILE --dockerfile FILE
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile
import time
import urllib.error
import urllib.request

LIBRARY = re.compile(r"\.so(\.[0-9]+)*$")


def read_package_list(path):
    with open(path, encoding="utf-8") as listing:
        return [line.strip() for line in listing if line.strip() and not line.startswith("#")]


def dockerfile_installs_list(dockerfile):
    """The runtime stage must install from the list, not from a copy of it."""
    text = open(dockerfile, encoding="utf-8").read()
    runtime = text.partition(" AS runtime")[2]
    return "runtime-packages.txt" in runtime and "apt-get install" in runtime


def loaded_by_server(server):
    """The shared objects mapped into a ready oer-server."""
    with tempfile.TemporaryDirectory() as data:
        process = subprocess.Popen(
            [server, "--port", "0", "--admin-port", "0", "--data-dir", data,
             "--access-log", "off"],
            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            admin = None
            deadline = time.monotonic() + 120
            for line in process.stdout:
                match = re.search(r"admin listener .*: (http://\S+)", line)
                if match:
                    admin = match.group(1)
                    break
            if admin is None:
                raise RuntimeError("oer-server printed no admin listener: "
                                   + process.stderr.read())
            while True:
                try:
                    with urllib.request.urlopen(admin + "/readyz", timeout=5) as answer:
                        if answer.status == 200:
                            break
                except (urllib.error.URLError, ConnectionError):
                    pass
                if time.monotonic() > deadline:
                    raise RuntimeError("oer-server was not ready within 120 s")
                time.sleep(0.2)
            with open(f"/proc/{process.pid}/maps", encoding="utf-8") as maps:
                paths = {line.split()[5] for line in maps if len(line.split()) >= 6}
        finally:
            process.terminate()
            process.wait(timeout=30)
    return {path for path in paths if LIBRARY.search(os.path.basename(path))}


def loaded_by_cli(cli):
    """The shared objects ldd resolves for the command line."""
    output = subprocess.run(["ldd", cli], check=True, capture_output=True, text=True).stdout
    paths = set()
    for line in output.splitlines():
        match = re.search(r"=> (/\S+)", line) or re.match(r"\s*(/\S+)", line)
        if match:
            paths.add(match.group(1))
    return paths


def owning_packages(paths):
    """{path: package or None}, trying the path as mapped, resolved, and without /usr (Debian
    12's merged /usr: dpkg knows /lib/x86_64-linux-gnu/libc.so.6, the loader maps /usr/lib/...).
    One dpkg-query for all of them: it prints "package: path" for each path it knows."""
    candidates = {}
    for path in paths:
        forms = []
        for form in (path, os.path.realpath(path)):
            forms.append(form)
            if form.startswith("/usr/lib/"):
                forms.append(form[len("/usr"):])
        candidates[path] = forms
    every_form = sorted({form for forms in candidates.values() for form in forms})
    output = subprocess.run(["dpkg-query", "-S", *every_form], capture_output=True,
                            text=True).stdout
    known = {}
    for line in output.splitlines():
        owners, _, path = line.partition(": ")
        known[path] = owners.split(",")[0].split(":")[0].strip()
    return {path: next((known[f] for f in forms if f in known), None)
            for path, forms in candidates.items()}


def installed_packages():
    """{name: (priority, [dependency groups], [provided names])} of the installed packages."""
    output = subprocess.run(
        ["dpkg-query", "-W", "-f",
         "${db:Status-Status}\t${Package}\t${Priority}\t${Pre-Depends}\t${Depends}\t"
         "${Provides}\n"],
        check=True, capture_output=True, text=True).stdout
    packages = {}
    for line in output.splitlines():
        status, name, priority, pre_depends, depends, provides = line.split("\t")
        if status != "installed":
            continue
        groups = []
        for field in (pre_depends, depends):
            for group in filter(None, (g.strip() for g in field.split(","))):
                groups.append([bare_name(alternative) for alternative in group.split("|")])
        packages[name] = (priority, groups, [bare_name(p) for p in provides.split(",") if p])
    return packages


def bare_name(relation):
    """'libc6:any (>= 2.34)' -> 'libc6'."""
    return relation.strip().split(" ")[0].split(":")[0]


def closure(roots, packages):
    """Every installed package reachable from roots through Pre-Depends and Depends."""
    providers = {}
    for name, (_, _, provided) in packages.items():
        for virtual in provided:
            providers.setdefault(virtual, []).append(name)

    def resolve(alternatives):
        # apt installs the first alternative it can; here, the first one installed (directly
        # or through a package that provides it).
        for alternative in alternatives:
            if alternative in packages:
                return [alternative]
            if alternative in providers:
                return providers[alternative][:1]
        return []

    reached, pending = set(), list(roots)
    while pending:
        name = pending.pop()
        if name in reached or name not in packages:
            continue
        reached.add(name)
        for group in packages[name][1]:
            pending.extend(resolve(group))
    return reached


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--server", required=True)
    parser.add_argument("--cli", required=True)
    parser.add_argument("--packages", required=True)
    parser.add_argument("--dockerfile", required=True)
    args = parser.parse_args()

    failures = []
    if not dockerfile_installs_list(args.dockerfile):
        failures.append(f"{args.dockerfile}: the runtime stage does not install from "
                        f"{os.path.basename(args.packages)}")
    listed = read_package_list(args.packages)
    packages = installed_packages()
    for name in listed:
        if name not in packages:
            failures.append(f"{name} (listed) is not installed here, so its dependencies are "
                            "unknown: install it, or correct the name")
    provided = closure(listed, packages)
    base = closure([n for n, (priority, _, _) in packages.items() if priority == "required"],
                   packages)

    libraries = loaded_by_server(args.server) | loaded_by_cli(args.cli)
    binaries = {os.path.realpath(args.server), os.path.realpath(args.cli)}
    libraries = {path for path in libraries if os.path.realpath(path) not in binaries}
    owners = owning_packages(libraries)
    for path, owner in sorted(owners.items()):
        if owner is None:
            failures.append(f"{path}: no Debian package owns it (built by hand?)")
        elif owner not in provided and owner not in base:
            failures.append(f"{path}: from {owner}, which neither {args.packages} nor the "
                            "base image provides")
    print(f"{len(libraries)} shared libraries loaded, from "
          f"{len(set(o for o in owners.values() if o))} packages; the list's {len(listed)} "
          f"packages bring {len(provided)} with their dependencies, the base image "
          f"{len(base)}")
    print("GL libraries loaded: " + ", ".join(sorted(
        os.path.basename(p) for p in libraries
        if re.search(r"EGL|GL|dri|LLVM|glapi", os.path.basename(p)))))
    for failure in failures:
        print("FAIL: " + failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
