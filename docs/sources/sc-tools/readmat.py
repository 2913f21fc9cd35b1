#!/usr/bin/env python3
# Minimal MAT v5 reader (double/char/struct/cell; prints names and values). Written for this task.
import sys, struct, zlib
TYPES={1:('b',1),2:('B',1),3:('h',2),4:('H',2),5:('i',4),6:('I',4),7:('f',4),9:('d',8),12:('q',8),13:('Q',8),16:('B',1),17:('H',2),18:('I',4)}
CLS={1:'cell',2:'struct',3:'object',4:'char',5:'sparse',6:'double',7:'single',8:'int8',9:'uint8',10:'int16',11:'uint16',12:'int32',13:'uint32',14:'int64',15:'uint64',16:'function',17:'opaque'}
def elements(buf, off, end):
    while off < end:
        t, n = struct.unpack_from('<II', buf, off)
        if t >> 16:  # small element
            n = t >> 16; t &= 0xffff
            yield t, buf[off+4:off+4+n]; off += 8
        else:
            yield t, buf[off+8:off+8+n]; off += 8 + n + (0 if t == 15 else (8 - n % 8) % 8)
def num(t, data):
    c, s = TYPES[t]; return list(struct.unpack('<%d%s' % (len(data)//s, c), data))
def matrix(data, ind=''):
    els = list(elements(data, 0, len(data)))
    if not els: return None
    flags = num(els[0][0], els[0][1]); cls = flags[0] & 0xff
    dims = num(els[1][0], els[1][1]); name = els[2][1].decode('latin1')
    if cls in (6,7,8,9,10,11,12,13,14,15):
        re = num(*els[3]); return name, CLS[cls], dims, re
    if cls == 4:
        v = num(*els[3]); return name, 'char', dims, ''.join(map(chr, v))
    if cls == 2:
        fl = num(*els[3])[0]; names = els[4][1]; fn = [names[i:i+fl].split(b'\0')[0].decode() for i in range(0, len(names), fl)]
        vals = [matrix(d) for t, d in els[5:]]
        return name, 'struct', dims, list(zip(fn * (len(vals)//max(1,len(fn))), vals))
    if cls == 1:
        return name, 'cell', dims, [matrix(d) for t, d in els[3:]]
    return name, CLS.get(cls, cls), dims, [(t, len(d), d[:64]) for t, d in els[3:]]
buf = open(sys.argv[1], 'rb').read()
for t, d in elements(buf, 128, len(buf)):
    if t == 15:
        d = zlib.decompress(d); t, d = next(elements(d, 0, len(d)))
    if t == 14:
        print(matrix(d))
    else:
        print('type', t, len(d))
