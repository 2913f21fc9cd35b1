"""Self-made reference traces (slx equations, RK4 h=1e-3), 35 s, outputs on a 0.01 s grid."""
import sc_sim as S, random
H=['t','Fs','y1_T','y2_Fcw','y3_Q','y4_P','P_internal','u_nn']
cases={}
cases['const_4.00']=(lambda t:4.0,[])
cases['const_3.99']=(lambda t:3.99,[])
cases['const_4.01']=(lambda t:4.01,[])
cases['step_3.99_to_4.01_at_10']=(lambda t:3.99 if t<10 else 4.01,[10.0])
cases['step_4.01_to_3.99_at_20']=(lambda t:4.01 if t<20 else 3.99,[20.0])
random.seed(20240601)
vals=[round(random.uniform(3.99,4.01),6) for _ in range(20)]
cases['inst2_random20']=(S.pwc(vals,1.75),[1.75*i for i in range(1,20)])
alt=[3.99 if i%2==0 else 4.01 for i in range(20)]
cases['inst2_alternating20']=(S.pwc(alt,1.75),[1.75*i for i in range(1,20)])
for name,(f,br) in cases.items():
    rows,_=S.simulate_slx(f,br,35.0,1e-3,out_dt=0.05)
    S.write_csv('ref/selfmade_slx_%s.csv'%name,H,rows)
    win=[r[5] for r in rows if 30-1e-9<=r[0]<=35+1e-9]
    rob=min(min(p-87,87.5-p) for p in win)
    print(name,'P(35)=%.6f'%rows[-1][5],'Pwin [%.5f, %.5f]'%(min(win),max(win)),'rob=%.5f'%rob)
open('ref/selfmade_slx_inst2_random20_pieces.txt','w').write('# 20 pieces of 1.75 s, Fs values\n'+'\n'.join('%.6f'%v for v in vals)+'\n')
