# Pavilion quick start (Debian 12):
#   make demo   installs dependencies, builds, runs the default scenario headless
#   make test   installs dependencies, builds, runs the test suite (all but the acceptance runs)
# Other targets: build, acceptance, format, format-check, asan-test, bench, clean.

BUILD      ?= build
ASAN_BUILD ?= build-asan
JOBS       ?= $(shell nproc)
SCENARIO   ?= scenarios/expo_day.yaml
# The demo runs the first minutes of the exhibition day: about a minute of wall
# time on the 2-core machine kind (docs/benchmarks.md, "The exhibition day"),
# long enough to hold the day's first staff push (691.7 s, seed 1).
DEMO_DURATION ?= 1200
DEMO_OUT   ?= out/demo

.PHONY: deps deps-test configure build demo test acceptance format format-check asan-test bench clean

deps:
	bash scripts/install-deps.sh

# The tests also need headless Chromium (the report's browser test).
deps-test:
	bash scripts/install-deps.sh --test

configure: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release

build: configure
	cmake --build $(BUILD) -j $(JOBS)

# Exit 3 (an expectation failed) still shows the demo: expo_day's expectations
# judge a whole day, and a few minutes of another seed may hold no kidnap or push
# to recover from.
demo: build
	./$(BUILD)/pavilion run $(SCENARIO) --duration $(DEMO_DURATION) --out $(DEMO_OUT) || test $$? -eq 3
	@echo "demo report: $(DEMO_OUT)/report.html (a shortened day: $(DEMO_DURATION) simulated s of $(SCENARIO))"

test: deps-test build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS) -LE acceptance

# The long acceptance runs (full-length scenarios, many seeds): not in CI;
# their figures go to docs/benchmarks.md with this command.
acceptance: build
	ctest --test-dir $(BUILD) --output-on-failure -j $(JOBS) -L acceptance

format: configure
	cmake --build $(BUILD) --target format

format-check: configure
	cmake --build $(BUILD) --target format-check

# Unit tests under AddressSanitizer + UndefinedBehaviorSanitizer; Mesa's own
# leaks are suppressed (tests/sanitizers/lsan.supp).
asan-test: deps
	cmake -S . -B $(ASAN_BUILD) -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPAVILION_SANITIZE=ON \
	  -DPAVILION_BUILD_BENCHMARKS=OFF
	cmake --build $(ASAN_BUILD) -j $(JOBS) --target unit_tests
	LSAN_OPTIONS=suppressions=$(CURDIR)/tests/sanitizers/lsan.supp \
	  ctest --test-dir $(ASAN_BUILD) --output-on-failure -j $(JOBS) -L unit -LE 'acceptance|integration'

bench: build
	./$(BUILD)/tests/bench/physics_bench --benchmark_counters_tabular=true
	./$(BUILD)/tests/bench/laser_bench --benchmark_counters_tabular=true
	./$(BUILD)/tests/bench/crowd_bench --benchmark_counters_tabular=true

clean:
	rm -rf $(BUILD) $(ASAN_BUILD) out
