import solver, math, time
from bench.instant import STEPS, plain_b
s = solver.load_scene('four_bar').everything()
u = s.compiled()
print(sum(u.core(p, 2.0, 0.5) is None for p in STEPS), "misses of", len(STEPS), u.paths, u.traces)
f = u.function
for _ in range(3):
    t = time.perf_counter()
    for _ in range(20):
        for p in STEPS: f(p, 2.0, 0.5)
    a = time.perf_counter() - t
    t = time.perf_counter()
    for _ in range(20):
        for p in STEPS: plain_b(p)
    b = time.perf_counter() - t
    print(a/7200*1e6, b/7200*1e6, a/b)
