# The closed planar N-bar chain of codegen::fixtures::closed_chain_source(N), written as
# a .mech file: python3 closed_chain.py N > chainN.mech
import sys, math
n=int(sys.argv[1])
def arch(n):
    shape=lambda a:[a*(n+1-2*i)/n for i in range(1,n+1)]
    ex=lambda a: sum(math.cos(t) for t in shape(a))-n/2
    lo,hi=0.0,math.pi
    for _ in range(200):
        m=0.5*(lo+hi)
        if ex(m)>0: lo=m
        else: hi=m
    return shape(0.5*(lo+hi))
th=arch(n)
o=[]
o.append(f"pub struct ClosedChain{n};")
o.append("parameters { g = 9.81; }")
o.append("coordinates { "+" ".join(f"th{i+1} = {t:.12f};" for i,t in enumerate(th))+" }")
o.append("independent { "+" ".join(f"th{i+1} = {th[i]:.12f}; der(th{i+1}) = 0.0;" for i in range(n-2))+" }")
terms=[]
for i in range(1,n+1):
    xs=" + ".join([f"cos(th{j})*der(th{j})" for j in range(1,i)]+[f"1/2*cos(th{i})*der(th{i})"])
    ys=" + ".join([f"sin(th{j})*der(th{j})" for j in range(1,i)]+[f"1/2*sin(th{i})*der(th{i})"])
    terms.append(f"1/2*((-({ys}))^2 + ({xs})^2) + 1/24*der(th{i})^2")
o.append("kinetic = "+"\n    + ".join(terms)+"\n;")
pot=" + ".join("("+" + ".join([f"sin(th{j})" for j in range(1,i)]+[f"1/2*sin(th{i})"])+")" for i in range(1,n+1))
o.append(f"potential = g*({pot});")
o.append("constraints {\n    "+" + ".join(f"cos(th{i})" for i in range(1,n+1))+f" - {n}/2;\n    "+" + ".join(f"sin(th{i})" for i in range(1,n+1))+";\n}")
print("\n".join(o))
