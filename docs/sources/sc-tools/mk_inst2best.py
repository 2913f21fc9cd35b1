import sc_sim as S
vals=[float(l) for l in open('ref/selfmade_pattern_inst2_20x1.75s_max_P.txt') if l.strip()]
rows,_=S.simulate_slx(S.pwc(vals,1.75),[1.75*i for i in range(1,20)],35.0,1e-3,out_dt=0.05)
S.write_csv('ref/selfmade_slx_inst2_best_pattern.csv',['t','Fs','y1_T','y2_Fcw','y3_Q','y4_P','P_internal','u_nn'],rows)
vals=[float(l) for l in open('ref/selfmade_pattern_175x0.2s_max_P.txt') if l.strip()]
rows,_=S.simulate_slx(S.pwc(vals,0.2),[0.2*i for i in range(1,175)],35.0,1e-3,out_dt=0.05)
S.write_csv('ref/selfmade_slx_175x0.2s_max_P_pattern.csv',['t','Fs','y1_T','y2_Fcw','y3_Q','y4_P','P_internal','u_nn'],rows)
