#!/usr/bin/env python3
"""Print, for every block of an unzipped .slx, the semantically relevant parameters with the
defaults of that file's own bddefaults.xml filled in (Simulink omits parameters equal to default)."""
import sys, os, xml.etree.ElementTree as ET
KEYS = ["Value","Gain","Inputs","Operator","Function","Criteria","Threshold","Time","Before","After",
        "InitialCondition","InitialValue","InitialOutput","UpperLimit","LowerLimit","Expr","Table",
        "BreakpointsForDimension1","BreakpointsForDimension2","InterpMethod","ExtrapMethod",
        "UseLastTableValue","Numerator","Denominator","Period","PulseWidth","PhaseDelay","Amplitude",
        "PulseType","SampleTime","VariableDelayType","MaximumDelay","MaximumPoints","OutDataTypeStr",
        "DataStoreName","GotoTag","TagVisibility","StatesWhenEnabling","TriggerType","CaseConditions",
        "OutputWhenDisabled","Port","RndMeth","ParamDataTypeStr","IconShape"]
d = sys.argv[1]
defs = {}
for bpd in ET.parse(os.path.join(d,"simulink/bddefaults.xml")).getroot().iter("BlockParameterDefaults"):
    for b in bpd.findall("Block"):
        defs[b.get("BlockType")] = {p.get("Name"): (p.text or "").strip() for p in b.findall("P")}
root = ET.parse(os.path.join(d,"simulink/blockdiagram.xml")).getroot()
def walk(sysel, path):
    for b in sysel.findall("Block"):
        bt = b.get("BlockType"); name = b.get("Name").replace("\n"," ")
        eff = dict(defs.get(bt, {}))
        eff.update({p.get("Name"): (p.text or "").strip() for p in b.findall("P")})
        items = [f"{k}={eff[k]!r}" for k in KEYS if k in eff]
        if bt not in ("Scope",):
            print(f"{path}/{name} [{bt}] SID={b.get('SID')}: " + "; ".join(items))
        for s in b.findall("System"):
            walk(s, f"{path}/{name}")
walk(root.find("Model").find("System"), "")
