"""Strips an AnimatLab project down to what host/src/model/aproj.rs reads: the fuzz seeds of
`aproj` (fuzz/seeds/aproj/*.aproj, from ../shared/models/animatlab/, 7 to 9 times smaller; each
imports to the same model, checked with `dbot model export --toml`). Usage: strip_aproj.py IN OUT"""
import sys, xml.etree.ElementTree as ET
LEAF = {"Name", "Mass", "COM", "Length", "Height", "Width", "LocalPosition", "Rotation",
        "EnableLimits", "EnableMotor", "LowerLimit", "UpperLimit", "MassUnits"}
BODY = {"RigidBody", "Joint", "ChildBodies", "Organism"}
def has(e, tags):
    return any(d.tag in tags for d in e.iter())
def strip(e, inside):
    for c in list(e):
        if inside or c.tag in BODY:
            if c.tag in LEAF:
                continue
            if c.tag in BODY:
                strip(c, True)
                continue
            e.remove(c)
        elif has(c, {"Organism", "MassUnits"}):
            strip(c, False)
        else:
            e.remove(c)
t = ET.parse(sys.argv[1]); r = t.getroot(); strip(r, False)
for lim in list(r.iter("LowerLimit")) + list(r.iter("UpperLimit")):
    for c in list(lim):
        if c.tag != "LimitPos":
            lim.remove(c)
for e in r.iter():
    for a in list(e.attrib):
        if a not in ("Value", "Scale"):
            del e.attrib[a]
    if e.text is not None and not e.text.strip():
        e.text = None
    e.tail = None
t.write(sys.argv[2], encoding="unicode")
