# farfield: `make demo` and `make test` install what is missing, build, and run.
BUILD ?= build
JOBS ?= $(shell nproc)
CMAKE_FLAGS ?= -G Ninja -DCMAKE_BUILD_TYPE=Release
OUT ?= out

PREFIX ?= /usr/local

.PHONY: deps build install demo test bench fuzz clean

deps:
	@bash scripts/install-deps.sh

build: deps
	@cmake -S . -B $(BUILD) $(CMAKE_FLAGS) > /dev/null
	@cmake --build $(BUILD) -j $(JOBS)

# farfield on the PATH: $(PREFIX)/bin/farfield (one self-contained binary).
install: build
	@cmake --install $(BUILD) --prefix $(PREFIX)

# The main job on the built-in default scene: the default city, its street path, the bakes of
# stratified rendering (the viewcells the path needs) and of clusters (every object's LODs),
# and a benchmark of brute force against octree culling, stratified rendering, composite and
# clusters, with bird's-eye pictures (report in $(OUT)/bench); then the generated building
# walked room to room, brute force against portal rendering (report in $(OUT)/bench-building).
# Colour cubes suit dense geometry seen from afar, not a city at street level: their bake
# refuses the city (docs/techniques/colorcube.md, "When it applies").
demo: build
	@mkdir -p $(OUT)
	$(BUILD)/farfield generate city --out $(OUT)/city.ffscene
	$(BUILD)/farfield info $(OUT)/city.ffscene
	$(BUILD)/farfield path $(OUT)/city.ffscene --kind street --out $(OUT)/street.json
	$(BUILD)/farfield bake $(OUT)/city.ffscene --technique stratified \
	  --set stratified.path=$(OUT)/street.json --out $(OUT)/city.ffpack
	$(BUILD)/farfield bake $(OUT)/city.ffscene --technique clusters --out $(OUT)/city.ffpack
	$(BUILD)/farfield bench $(OUT)/city.ffscene --path $(OUT)/street.json --store $(OUT)/city.ffpack \
	  --technique brute,octree,stratified,composite,clusters --birdseye 300 --out $(OUT)/bench
	$(BUILD)/farfield generate building --out $(OUT)/building.ffscene
	$(BUILD)/farfield path $(OUT)/building.ffscene --kind interior --out $(OUT)/interior.json
	$(BUILD)/farfield bench $(OUT)/building.ffscene --path $(OUT)/interior.json \
	  --technique brute,portal,portal-paper --birdseye 30 --out $(OUT)/bench-building
	@echo "demo: reports in $(OUT)/bench (the city) and $(OUT)/bench-building (portals through the building's rooms): bench.json, frame_times.png, sample frames and differences"

test: build
	cd $(BUILD) && ctest --output-on-failure -j $(JOBS)

# Google Benchmark targets (not part of the correctness run).
bench: build
	@for b in $(BUILD)/bench_*; do $$b; done

# libFuzzer targets, built with clang into build-fuzz; FUZZ_SECONDS per target. Every reader of
# a file or blob has one: scene files, packs (and the decoders), camera paths, bake records,
# colour-cube trees, stratified viewcells, texture images, clusters LOD sets and hierarchies
# (with the bake's work batches), hybrid's visible-triangle streams. Seeds in
# fuzz/corpus/NAME, findings in build-fuzz.
FUZZ_SECONDS ?= 60
FUZZ_TARGETS = scene_file store camera_path bake_record cube_tree stratified_pack texture_image lod_set cluster_tree occupancy
fuzz: deps
	@cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
	  -DCMAKE_CXX_COMPILER=clang++-14 -DFARFIELD_FUZZ=ON -DFARFIELD_TESTS=OFF \
	  -DFARFIELD_BENCH=OFF -DFARFIELD_MPI=OFF > /dev/null
	@cmake --build build-fuzz -j $(JOBS)
	@for t in $(FUZZ_TARGETS); do \
	  mkdir -p build-fuzz/corpus-$$t && \
	  build-fuzz/fuzz_$$t -max_total_time=$(FUZZ_SECONDS) -rss_limit_mb=4096 \
	    -artifact_prefix=build-fuzz/crash-$$t- build-fuzz/corpus-$$t fuzz/corpus/$$t \
	    || exit 1; \
	done

clean:
	rm -rf $(BUILD) build-fuzz
