# The two commands of the README: `make run` and `make test`. Everything else is a helper.
BUILD ?= build
ARCH ?= native
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?=

.PHONY: all deps test-deps build run test test-numa clean

all: build

deps:
	@scripts/install-deps.sh build

test-deps:
	@scripts/install-deps.sh test

# Configured every time, so ARCH=... and CMAKE_FLAGS=... take effect on an existing build too.
build: deps
	cmake -S . -B $(BUILD) -DCMAKE_BUILD_TYPE=Release -DSUITE_ARCH=$(ARCH) $(CMAKE_FLAGS) > /dev/null
	cmake --build $(BUILD) -j $(JOBS)

# The default sweep: a table on the console and results/latest.json.
run: build
	./suite --out=results/latest.json

test: test-deps build
	cd $(BUILD) && ctest --output-on-failure -j 2
	@JOBS=$(JOBS) scripts/numa-vm/run.sh

# Placement and pinning on an emulated two-node NUMA machine (QEMU); its files go to build-numa/.
test-numa: test-deps
	@JOBS=$(JOBS) scripts/numa-vm/run.sh

clean:
	rm -rf $(BUILD) suite
