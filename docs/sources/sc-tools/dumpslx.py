#!/usr/bin/env python3
# Dump blocks (non-graphical parameters) and lines of an unzipped .slx blockdiagram.xml
import sys, xml.etree.ElementTree as ET
root=ET.parse(sys.argv[1]).getroot()
m=root.find('Model')
SKIP=('Position','ZOrder','Ports','BackgroundColor','ForegroundColor','FontName','FontSize','ShowName','NamePlacement','BlockMirror','BlockRotation','ContentPreviewEnabled','LibraryVersion','DropShadow','IconDisplay','Orientation','ScopeSpecificationString','SourceProductName','SourceProductBaseCode','IconShape','SaturateOnIntegerOverflow','DisplayOption','HideAutomaticName')
def walk(sysel, depth):
    for b in sysel.findall('Block'):
        name=b.get('Name').replace('\n',' ')
        ps={q.get('Name'):(q.text or '').replace('\n',' ') for q in b.findall('P')}
        for inst in b.findall('InstanceData'):
            ps.update({'I:'+q.get('Name'):(q.text or '') for q in inst.findall('P')})
        for mk in b.findall('Mask'):
            for mp in mk.iter('MaskParameter'):
                v=mp.find('Value'); ps['M:'+mp.get('Name')]=(v.text if v is not None else '')
        keep={k:v for k,v in ps.items() if k.split(':')[-1] not in SKIP}
        print('  '*depth+f"[{b.get('SID')}] {b.get('BlockType')} '{name}' {keep}")
        for s in b.findall('System'):
            walk(s, depth+1)
    for l in sysel.findall('Line'):
        ps={q.get('Name'):(q.text or '') for q in l.findall('P')}
        br=[{q.get('Name'):(q.text or '') for q in bb.findall('P')} for bb in l.iter('Branch')]
        print('  '*depth+f"LINE {ps.get('Name','')} {ps.get('Src')} -> {ps.get('Dst')} {[x.get('Dst') for x in br if x.get('Dst')]}")
walk(m.find('System'),0)
