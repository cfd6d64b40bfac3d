"""Reads a Unity project's materials as HDRP does, independently of
scatterlab's Rust code, for the `scatterlab budget` tests: every
`_DiffusionProfileAsset*` / `*_Asset` colour turned back into a GUID by
HDRP's HDUtils.ConvertVector4ToGUID (four little-endian floats, their 16
bytes in order as hex), and whether the hash float beside it is the hash
HDRP gives that GUID (DiffusionProfileHashTable.GetDiffusionProfileHash,
typed in tests/data/unity_budget/make_fixture.py). Also the `hash:` of
every profile asset against its .meta GUID, and the GUIDs a Diffusion
Profile List names.

Usage: python unity_budget_check.py PROJECT_OR_FOLDER
Prints one JSON line: {"materials": {path: [[property, guid, hash_ok]]},
"profiles": {path: [guid, hash_ok]}, "lists": {path: [guids]}}.
"""

import json
import os
import re
import struct
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "unity_budget"))
from make_fixture import profile_hash  # noqa: E402

COLOUR = re.compile(r"^\s*- (\S+): \{r: ([^,]+), g: ([^,]+), b: ([^,]+), a: ([^}]+)\}")
FLOAT = re.compile(r"^\s*- (\S+): (\S+)\s*$")


def main():
    root = sys.argv[1]
    out = {"materials": {}, "profiles": {}, "lists": {}}
    for d, _, files in os.walk(root):
        for f in sorted(files):
            path = os.path.join(d, f)
            rel = os.path.relpath(path, root)
            if f.endswith(".mat"):
                text = open(path).read()
                floats = dict(m.groups() for m in map(FLOAT.match, text.splitlines()) if m)
                refs = []
                for line in text.splitlines():
                    m = COLOUR.match(line)
                    if not m:
                        continue
                    key = m.group(1)
                    if key.startswith("_DiffusionProfileAsset"):
                        hash_key = "_DiffusionProfileHash" + key[len("_DiffusionProfileAsset"):]
                    elif key.endswith("_Asset") and key[:-6] in floats:
                        hash_key = key[:-6]
                    else:
                        continue
                    vec = [float(x) for x in m.groups()[1:]]
                    guid = struct.pack("<4f", *vec).hex()
                    h = struct.unpack("<I", struct.pack("<f", float(floats[hash_key])))[0]
                    refs.append([key, guid, h == profile_hash(guid)])
                out["materials"][rel] = refs
            elif f.endswith(".asset") and os.path.exists(path + ".meta"):
                text = open(path).read()
                guid = re.search(r"^guid: (\w+)", open(path + ".meta").read(), re.M).group(1)
                m = re.search(r"^\s+hash: (\d+)", text, re.M)
                if "b2686e09ec7aef44bad2843e4416f057" in text and m:
                    out["profiles"][rel] = [guid, int(m.group(1)) == profile_hash(guid)]
                if "diffusionProfiles:" in text:
                    out["lists"][rel] = re.findall(r"guid: (\w+), type: 2", text)
    print(json.dumps(out))


if __name__ == "__main__":
    main()
