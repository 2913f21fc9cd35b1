"""Rough emulation of Simulink's ode45 (Dormand-Prince 5(4)) with the .slx settings: RelTol 1e-3,
AbsTol 'auto' (emulated: 1e-6 initially, then RelTol*max|x_i| seen so far), MaxStep 0.1, the step at
t=2 located exactly (zero crossing), input = 0.01 s samples linearly interpolated (Inport Interpolate on,
as ARCH's run_steamcondenser.m feeds interp1 'previous' on 0:0.01:T), outputs at the solver's steps.
Purpose: size of the solver error in P relative to the requirement margins. Not Simulink."""
import sc_sim as S, math, csv, sys
C=[0,1/5,3/10,4/5,8/9,1,1]
A=[[],[1/5],[3/40,9/40],[44/45,-56/15,32/9],[19372/6561,-25360/2187,64448/6561,-212/729],
   [9017/3168,-355/33,46732/5247,49/176,-5103/18656],[35/384,0,500/1113,125/192,-2187/6784,11/84]]
B5=[35/384,0,500/1113,125/192,-2187/6784,11/84,0]
B4=[5179/57600,0,7571/16695,393/640,-92097/339200,187/2100,1/40]
def ode45(fs_fun,t_end=35.0,rtol=1e-3,hmax=0.1):
    x=S.x_init(); t=0.0; out=[(0.0,x[2])]
    atol=[1e-6]*10; xmax=[abs(v) for v in x]
    h=1e-3
    for (ta,tb) in ((0.0,2.0),(2.0,t_end)):
        sp87= ta>=2.0; t=ta
        while t<tb-1e-12:
            h=min(h,hmax,tb-t)
            K=[]
            for s in range(7):
                xs=[x[i]+h*sum(A[s][j]*K[j][i] for j in range(s)) for i in range(10)]
                K.append(S.rhs(sp87,xs,fs_fun(t+C[s]*h)))
            x5=[x[i]+h*sum(B5[j]*K[j][i] for j in range(7)) for i in range(10)]
            x4=[x[i]+h*sum(B4[j]*K[j][i] for j in range(7)) for i in range(10)]
            err=max(abs(x5[i]-x4[i])/max(rtol*max(abs(x[i]),abs(x5[i])),atol[i]) for i in range(10))
            if err<=1.0:
                t+=h; x=x5; out.append((t,x[2]))
                for i in range(10):
                    xmax[i]=max(xmax[i],abs(x[i])); atol[i]=rtol*max(xmax[i],1e-3)  # auto AbsTol, emulated
            h=h*min(5.0,max(0.2,0.9*(1.0/max(err,1e-10))**0.2))
    return out
def rob(out):
    return min(min(p-87,87.5-p) for (t,p) in out if 30-1e-9<=t<=35+1e-9)
if __name__=='__main__':
    for f in sys.argv[1:]:
        if f.endswith('.txt'):
            vals=[float(l) for l in open(f) if l.strip()]; dt=35.0/len(vals)
            rows=None; fs=[vals[min(int(math.floor(k*0.01/dt+1e-9)),len(vals)-1)] for k in range(3601)]
        else:
            fs=[float(r[1]) for r in csv.reader(open(f))]
        def fb(t):
            k=int(math.floor(t/0.01+1e-9)); k=min(k,len(fs)-2); w=(t-0.01*k)/0.01
            return fs[k]+(fs[k+1]-fs[k])*w
        out=ode45(fb)
        print(f, 'ode45-emul steps',len(out),'rob %.5f'%rob(out), 'Pwin [%.5f,%.5f]'%(min(p for t,p in out if 30<=t<=35),max(p for t,p in out if 30<=t<=35)),flush=True)
