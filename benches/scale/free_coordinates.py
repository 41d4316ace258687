# N free particles on springs (T = 1/2 sum q_i^2, Pi = sum q_i^2), no constraint rows:
# python3 free_coordinates.py N > freeN.mech
import sys
n=int(sys.argv[1])
print(f"pub struct Free{n};")
print("coordinates { "+" ".join(f"q{i} = 0.1;" for i in range(1,n+1))+" }")
print("kinetic = 1/2*("+" + ".join(f"der(q{i})^2" for i in range(1,n+1))+");")
print("potential = "+" + ".join(f"q{i}^2" for i in range(1,n+1))+";")
