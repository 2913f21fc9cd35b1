"""Dump the aero/engine tables of AeroBenchVVPython as markdown + JSON, oriented
rows = first lookup variable (alpha or Mach), columns = second variable."""
import ast, json, sys
base = '/work/f16-notes/aerobench/code/aerobench/lowlevel/'
def literals(fname):
    tree = ast.parse(open(base + fname).read())
    out = {}
    for node in ast.walk(tree):
        if isinstance(node, ast.Assign) and isinstance(node.value, (ast.Attribute, ast.Call)):
            name = node.targets[0].id if isinstance(node.targets[0], ast.Name) else None
            call = node.value.value if isinstance(node.value, ast.Attribute) else node.value
            if isinstance(call, ast.Call) and getattr(call.func, 'attr', '') == 'array':
                out[name] = (ast.literal_eval(call.args[0]), node.lineno, node.end_lineno)
    return out
ALPHA = list(range(-10, 50, 5))
spec = [
 ('CX', 'cx.py', 'a', 'alpha_deg', ALPHA, 'elevator_deg', [-24, -12, 0, 12, 24]),
 ('CM', 'cm.py', 'a', 'alpha_deg', ALPHA, 'elevator_deg', [-24, -12, 0, 12, 24]),
 ('CL', 'cl.py', 'a', 'alpha_deg', ALPHA, 'abs_beta_deg', [0, 5, 10, 15, 20, 25, 30]),
 ('CN', 'cn.py', 'a', 'alpha_deg', ALPHA, 'abs_beta_deg', [0, 5, 10, 15, 20, 25, 30]),
 ('DLDA', 'dlda.py', 'a', 'alpha_deg', ALPHA, 'beta_deg', [-30, -20, -10, 0, 10, 20, 30]),
 ('DLDR', 'dldr.py', 'a', 'alpha_deg', ALPHA, 'beta_deg', [-30, -20, -10, 0, 10, 20, 30]),
 ('DNDA', 'dnda.py', 'a', 'alpha_deg', ALPHA, 'beta_deg', [-30, -20, -10, 0, 10, 20, 30]),
 ('DNDR', 'dndr.py', 'a', 'alpha_deg', ALPHA, 'beta_deg', [-30, -20, -10, 0, 10, 20, 30]),
 ('DAMP', 'dampp.py', 'a', 'alpha_deg', ALPHA, 'coefficient', ['CXq', 'CYr', 'CYp', 'CZq', 'CLr', 'CLp', 'CMq', 'CNr', 'CNp']),
]
js = {}
md = []
for name, f, var, rlab, rbp, clab, cbp in spec:
    lit, l0, l1 = literals(f)[var]
    # source literal: one inner list per column-variable value, 12 alpha values each; code transposes (.T)
    M = [[lit[j][i] for j in range(len(cbp))] for i in range(len(rbp))]
    js[name] = {'source': 'code/aerobench/lowlevel/%s lines %d-%d' % (f, l0, l1), 'rows': rlab, 'row_breakpoints': rbp,
                'cols': clab, 'col_breakpoints': cbp, 'values': M}
    md.append('#### %s  (`aerobench/code/aerobench/lowlevel/%s`, lines %d-%d; python array shape after `.T`: %dx%d, index [alpha_idx, %s_idx])\n' % (name, f, l0, l1, len(rbp), len(cbp), clab))
    md.append('| %s \\ %s | ' % (rlab, clab) + ' | '.join(str(c) for c in cbp) + ' |')
    md.append('|' + '---|' * (len(cbp) + 1))
    for i, r in enumerate(rbp):
        md.append('| %s | ' % r + ' | '.join(repr(v) for v in M[i]) + ' |')
    md.append('')
lit, l0, l1 = literals('cz.py')['a']
js['CZ'] = {'source': 'code/aerobench/lowlevel/cz.py lines %d-%d' % (l0, l1), 'rows': 'alpha_deg', 'row_breakpoints': ALPHA, 'values': lit}
md.append('#### CZ base (`aerobench/code/aerobench/lowlevel/cz.py`, lines %d-%d; 1-D, 12 values)\n' % (l0, l1))
md.append('| alpha_deg | ' + ' | '.join(str(a) for a in ALPHA) + ' |')
md.append('|' + '---|' * 13)
md.append('| CZ0 | ' + ' | '.join(repr(v) for v in lit) + ' |\n')
lits = literals('thrust.py')
for key, lab in [('a', 'T_idle'), ('b', 'T_mil'), ('c', 'T_max')]:
    lit, l0, l1 = lits[key]
    # literal row = Mach index (0,0.2,...,1.0), literal column = altitude index (0,10k,...,50k ft); code does .T -> [alt_idx, mach_idx]
    js[lab] = {'source': 'code/aerobench/lowlevel/thrust.py lines %d-%d' % (l0, l1), 'rows': 'mach', 'row_breakpoints': [0, 0.2, 0.4, 0.6, 0.8, 1.0],
               'cols': 'alt_ft', 'col_breakpoints': [0, 10000, 20000, 30000, 40000, 50000], 'values': lit}
    md.append('#### %s, lbf (`aerobench/code/aerobench/lowlevel/thrust.py`, lines %d-%d; python array after `.T` is index [alt_idx, mach_idx])\n' % (lab, l0, l1))
    md.append('| Mach \\ alt_ft | 0 | 10000 | 20000 | 30000 | 40000 | 50000 |')
    md.append('|---|---|---|---|---|---|---|')
    for i, m in enumerate([0, 0.2, 0.4, 0.6, 0.8, 1.0]):
        md.append('| %s | ' % m + ' | '.join(repr(v) for v in lit[i]) + ' |')
    md.append('')
json.dump(js, open('/work/f16-notes/tables.json', 'w'), indent=1)
open('/work/f16-notes/tables.md', 'w').write('\n'.join(md) + '\n')
print('\n'.join(md))

# Morelli polynomial coefficients (name -> value), from morellif16.py
tree = ast.parse(open(base + 'morellif16.py').read())
coef = {}
for node in ast.walk(tree):
    if isinstance(node, ast.Assign) and isinstance(node.targets[0], ast.Name):
        try:
            v = ast.literal_eval(node.value)
        except Exception:
            continue
        if isinstance(v, (int, float)):
            coef[node.targets[0].id] = v
js['MORELLI'] = {'source': 'code/aerobench/lowlevel/morellif16.py lines 25-152 (formulas 155-187)', 'coefficients': coef}
json.dump(js, open('/work/f16-notes/tables.json', 'w'), indent=1)
