import solver, timeit, math
s = solver.load_scene('four_bar').everything()
u = s.compiled()
f = u.function
src = u.source
stripped = "\n".join(l for l in src.splitlines() if "return _miss" not in l or l.strip().startswith("return"))
ns = {}
exec(compile(stripped, "x", "exec"), ns)
import solver._codegen as cg
vals = [v for _, v in u._constants.values()]
g = ns["_factory"](None, solver.SolverError, *cg._MATH.values(), *vals)
n = 100000
for _ in range(2):
    print("compiled", timeit.timeit(lambda: f(0.7, 2.0, 0.5), number=n)/n*1e6)
    print("no guards", timeit.timeit(lambda: g(0.7, 2.0, 0.5), number=n)/n*1e6)
    print("empty lambda", timeit.timeit(lambda: None, number=n)/n*1e6)
    def plainB(phi=0.7):
        a = 0.1 * complex(math.cos(phi), math.sin(phi))
        d = 0.4 - a
        dd = d.real*d.real + d.imag*d.imag
        aa = (0.16 - 0.09 + dd) / (2*dd)
        h = math.sqrt(max(0.16/dd - aa*aa, 0.0))
        return a + d*(aa - 1j*h)
    print("plain B", timeit.timeit(plainB, number=n)/n*1e6)
