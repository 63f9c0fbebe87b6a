# Thin aliases for ./dev (which works without make on a fresh machine).
.PHONY: run test bench setup lint
run:
	./dev run
test:
	./dev test
bench:
	./dev bench
setup:
	./dev setup record,view,test
lint:
	.venv/bin/ruff check solver linkage_ros tests bench && .venv/bin/mypy
