#!/usr/bin/env python3
"""Dump the block hierarchy of a Simulink blockdiagram.xml (from an .slx zip) as readable text:
for every System: its blocks (type, name, SID, parameters) and its lines (src -> dst)."""
import sys, xml.etree.ElementTree as ET

SKIP = {"Position", "ZOrder", "BackgroundColor", "ForegroundColor", "ShowName", "Ports",
        "FontName", "FontSize", "DropShadow", "NamePlacement", "Orientation", "LibraryVersion",
        "IconDisplay", "BlockMirror", "BlockRotation", "MaskIconFrame", "MaskIconOpaque",
        "MaskIconRotate", "MaskPortRotate", "MaskIconUnits", "Location", "ScreenColor",
        "PaperOrientation", "PaperPositionMode", "PaperType", "PaperUnits", "TiledPaperMargins",
        "TiledPageScale", "ShowPageBoundaries", "ZoomFactor", "ReportName", "SIDHighWatermark",
        "Open", "ModelBrowserVisibility", "ModelBrowserWidth", "SIDPrevWatermark", "Points",
        "LinkStatus", "FontWeight", "FontAngle"}

def ptext(p):
    return (p.text or "").strip()

def dump_system(sysel, path, out, sids):
    blocks = sysel.findall("Block")
    out.append(f"\n==== SYSTEM {path}")
    for b in blocks:
        bt, name, sid = b.get("BlockType"), b.get("Name"), b.get("SID")
        sids[sid] = f"{path}/{name}"
        params = []
        for p in b.findall("P"):
            if p.get("Name") in SKIP: continue
            params.append(f"{p.get('Name')}={ptext(p)!r}")
        for ip in b.findall("InstanceData"):
            for p in ip.findall("P"):
                params.append(f"[inst]{p.get('Name')}={ptext(p)!r}")
        mask = b.find("Mask")
        if mask is not None:
            for mp in mask.iter("MaskParameter"):
                v = mp.find("Value")
                params.append(f"[mask]{mp.get('Name')}={(v.text if v is not None else '')!r}")
            for d in mask.iter("Display"):
                params.append(f"[maskdisplay]={(d.text or '')[:200]!r}")
            for init in mask.iter("Initialization"):
                params.append(f"[maskinit]={(init.text or '')!r}")
        out.append(f"  BLOCK {bt:24s} {name!r} SID={sid}")
        for pp in params:
            out.append(f"      {pp}")
    for ln in sysel.findall("Line"):
        src = [ptext(p) for p in ln.findall("P") if p.get("Name") == "Src"]
        dst = [ptext(p) for p in ln.findall("P") if p.get("Name") == "Dst"]
        nm = [ptext(p) for p in ln.findall("P") if p.get("Name") == "Name"]
        def branches(el):
            r = []
            for br in el.findall("Branch"):
                r += [ptext(p) for p in br.findall("P") if p.get("Name") == "Dst"]
                r += branches(br)
            return r
        dst += branches(ln)
        out.append(f"  LINE {src} -> {dst}" + (f" name={nm}" if nm else ""))
    for b in blocks:
        for sub in b.findall("System"):
            dump_system(sub, f"{path}/{b.get('Name')}", out, sids)

def main():
    tree = ET.parse(sys.argv[1])
    root = tree.getroot()
    model = root.find("Model")
    out = []
    for p in model.findall("P"):
        n = p.get("Name")
        if "Fcn" in n or n in ("Description",):
            out.append(f"MODEL {n} = {ptext(p)!r}")
    sids = {}
    dump_system(model.find("System"), "ROOT", out, sids)
    out.append("\n==== SID MAP")
    for k, v in sids.items():
        out.append(f"  {k}: {v}")
    print("\n".join(out))

main()
