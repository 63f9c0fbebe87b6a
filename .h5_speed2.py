import solver, timeit, math, numpy as np
s = solver.load_scene('four_bar').everything()
u = s.compiled()
f = u.function
n = 50000
def t(label, fn):
    print(f"{label:40s} {timeit.timeit(fn, number=n)/n*1e6:.2f} us")
t("compiled", lambda: f(0.7, 2.0, 0.5))
t("instant", lambda: s.instant(0.7, 2.0, 0.5))
t("solve", lambda: s.solve(0.7, omega=2.0, epsilon=0.5))
names = (*s.output_points, *s.output_joints)
def read():
    k = s.solve(0.7, omega=2.0, epsilon=0.5)
    for nm in names: k.floats(nm)
t("solve+floats all", read)
t("np.array x3", lambda: (np.array(0.7), np.array(2.0, float), np.array(0.5, float)))
