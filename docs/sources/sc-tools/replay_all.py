import sc_sim as S, csv, glob
out=[]
for f in sorted(glob.glob('zls_csv/*.csv')):
    rows=[list(map(float,r)) for r in csv.reader(open(f))]
    fs=[r[1] for r in rows]; pieces=[fs[20*i+10] for i in range(200)]
    ra,_=S.simulate_slx(S.pwc(pieces,0.2),[0.2*i for i in range(1,200)],35.0,2e-3)
    rob=min(min(r[5]-87,87.5-r[5]) for r in ra if 30-1e-9<=r[0]<=35+1e-9)
    out.append((f.split('/')[-1],rows[-1][6]-0.007,rob))
    print('%s %.5f %.5f'%out[-1],flush=True)
print('slx rob range',min(o[2] for o in out),max(o[2] for o in out),'n',len(out),'all<0',all(o[2]<0 for o in out))
