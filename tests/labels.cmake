# The CTest labels of suite_tests' GoogleTest tests: one area each, so that `ctest -L stats` runs
# the tests of one area and a mutant of tests/mutants/mutants.txt runs the tests that should kill it
# (scripts/mutants.py). Each suite_tests_label() call discovers the tests its gtest filter matches
# and that no earlier call took; the last call takes whatever is left (label `other`). So every test
# is discovered exactly once, whatever the filters say, and a new test suite runs in `make test`
# even before it is given an area. The Python tests get their labels beside their add_test lines.
#
# A filter is gtest's: patterns separated by ':', matched against the whole name ("Suite.Test",
# "Instance/Suite.Test/param"). The registry walk (AllKernels/Registry.*/KERNEL_PATTERN) is split
# by kernel, so that a kernel's area holds the check that verifies it.
set(suite_tests_taken "")
function(suite_tests_label label filter)
  if(suite_tests_taken)
    set(full "${filter}-${suite_tests_taken}")
    set(taken "${suite_tests_taken}:${filter}")
  else()
    set(full "${filter}")
    set(taken "${filter}")
  endif()
  gtest_discover_tests(suite_tests DISCOVERY_TIMEOUT 60 TEST_FILTER "${full}" PROPERTIES TIMEOUT 600 LABELS ${label})
  set(suite_tests_taken "${taken}" PARENT_SCOPE)
endfunction()

set(registry "AllKernels/Registry.*")
set(choices "AllChoices/RegistryChoice.*")
suite_tests_label(stats "Stats.*")
suite_tests_label(common "ChoiceTable.*:FormatBytes.*:Nearest.*:Parse*List.*:ParseBytes.*:ParseSeed.*:WholeNumbers.*:OutputDir.*:OutputFile.*:SysfsFile.*")
suite_tests_label(stream "${registry}/copy_*:${registry}/scale_*:${registry}/add_*:${registry}/triad_*:${registry}/sin_add_*:\
${registry}/load_*:${registry}/store_*:${registry}/latency_*:RegistryContents.*:\
E2E.NonTemporal*:E2E.StoreNt*:E2E.RandomAdd*")
suite_tests_label(kernels-fem "Fem*:Matrix*:${registry}/fem_*")
suite_tests_label(kernels-mpm "Mpm*:ParticlesVtk.*:${registry}/mpm_*:${choices}/mpm_*")
suite_tests_label(kernels-sfc "Sfc*:Traverse.*:${registry}/sfc_*")
suite_tests_label(kernels-mesh "Mesh*:Cases/BadMesh*")
suite_tests_label(kernel "AppKernelInterface.*:${registry}:${choices}")
suite_tests_label(results "Check.*:Compare.*:GateRule.*:History*:Dashboard.*:FuzzResults.*:Ranks.*:Mpi*:Deterministic.*:CallgrindDump.*")
suite_tests_label(reports "ResultSchema.*:GbenchFormat.*:SuiteGbench.*:ParamsFacts.*")
suite_tests_label(instruments "Counter*:TeamCountersTest.*:Energy*:PerfPower.*:Powercap.*:Instrument*:MachineLoad.*")
suite_tests_label(machine "CpuModel.*:Pinning.*:Placement.*:Topology.*:HugePages*:RankShare.*:E2E.ResultRecordsPinningAndPagesAsObserved")
suite_tests_label(measure "CacheProbe.*:OutputFormats.*:CacheSteps.*:Plan.*:PlanParams.*:PlanVariants.*:ParseFinite.*:RunOptionsCli.*")
suite_tests_label(cli "Cli*:Cases/CliErrorTest.*:CpuMask.*:E2E.*:Signals/*:ExitStatus.*:Faults.*:DirectoryOfOutputs.*:Memory.*:\
ValuesUsedSilently.*:Output.*:Readme.*:CommandFrame.*:Hardening.*")
suite_tests_label(bench "Bench.*")
suite_tests_label(other "*")
# A change of the labels changes the discovery commands, which run after suite_tests is linked:
# relink it then, or its tests would keep the lists of the former labels.
set_property(TARGET suite_tests APPEND PROPERTY LINK_DEPENDS ${CMAKE_CURRENT_LIST_FILE})
