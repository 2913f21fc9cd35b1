#!/usr/bin/env python3
# Print NN (NARMA-L2 mask parameters) or SC (Constant block values inside the RNN) from an unzipped .slx
import sys, xml.etree.ElementTree as ET, os
d, kind = sys.argv[1], sys.argv[2]
root = ET.parse(os.path.join(d, 'simulink/blockdiagram.xml')).getroot()
def walk(el, path):
    for b in el.findall('Block'):
        name = b.get('Name').replace('\n', ' ')
        yield b, path + '/' + name
        for s in b.findall('System'):
            yield from walk(s, path + '/' + name)
for b, p in walk(root.find('Model').find('System'), ''):
    if kind == 'nn':
        for mp in b.iter('MaskParameter'):
            v = mp.find('Value')
            print(f"{p}|{mp.get('Name')}|{(v.text if v is not None else '')}")
    else:
        if b.get('BlockType') in ('Constant', 'Gain', 'Fcn', 'Lookup', 'TransferFcn', 'Integrator', 'Saturate'):
            ps = {q.get('Name'): (q.text or '') for q in b.findall('P')}
            for k in ('Value', 'Gain', 'Expr', 'InputValues', 'Table', 'Numerator', 'Denominator', 'InitialCondition', 'UpperLimit', 'LowerLimit'):
                if k in ps: print(f"{p}|{k}|{ps[k]}")
