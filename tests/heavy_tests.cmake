# Read by ctest (TEST_INCLUDE_FILES of tests/coupling, tests/lbm and tests/app; see
# tests/CMakeLists.txt), after gtest_discover_tests has registered the tests: gives the extra
# label `heavy` to the numerical tests too slow for the sanitizer build. The debug test preset
# (scripts/run_sanitizer_tests.sh) leaves them out; the release preset runs them as before.
# They run the same library code as the lighter tests of their suites, for more steps or on
# larger grids. Seconds measured on the 2-core development machine with two tests at a time
# (docs/fuzzing.md): sanitizer build (library and front end instrumented, -O1 -g1) / release.
# scripts/run_sanitizer_tests.sh checks that every name here still exists.
set_tests_properties(
  SpheroidStokesDrag.ProlateBroadsideAt10CellsPerDiameter                     # 734 / 129
  RotatingSphere.StokesTorqueAt16CellsPerDiameter                             # 259 / 35
  RotatingSphere.MomentumExchangeStokesTorqueAt16CellsPerDiameter            # (not measured) / 64 on a loaded machine
  FailureAdvice.TheChangeAnUnderResolvedWakeIsToldToMakeCompletesTheRun        # (not measured) / 30: two runs of 3000-4500 steps on 1e5 cells
  OscillatingSphere.MomentumExchangeFollowsStokesAt12CellsPerDiameter         # (not measured) / 3.3 on two threads (native, 2026-12-02)
  PeriodicSphereArray.DilutePhi0065At16CellsPerDiameter                       # 145 / 26
  PeriodicSphereArray.ModeratePhi0155At16CellsPerDiameter                     # 42 / 3.6
  PeriodicSphereArray.InteriorMarkersDilutePhi0065At16CellsPerDiameter        # (not measured) / 7
  LbmTaylorGreen.TrtD3Q19EnergyDecayRateWithinOnePercentAt64Cubed             # 79 / 4.3
  LbmTaylorGreen.EveryLatticeCollisionAndPlaneDecaysAtTheRightRateAt32Cubed   # 36 / 2.9
  LbmTaylorGreen.CumulantDecayRateIsTheSameOnAUniformBackgroundFlow           # (not measured) / 2.4 on a loaded machine (the line above: 11.4 there)
  LbmStability.ShearLayerNearHalfTauBlowsUpBgkAndTrtButNotRecursiveRegularizedOrCumulant  # 31 / 3.3 before the cumulant run; 18.8 with it on a loaded machine
  WallContact.TiltedSpheroidLandsOnItsTipAndComesToRest                       # 62 / 6.6
  WallContact.SphereSettlesOntoTheBottomAndComesToRest                        # 39 / 3.3
  CouplingLightBody.AcrylicCubeAt8CellsStaysBoundedOverTheFirstTenthOfASecond  # 27 / 2.4
  # Measured 2026-11-26, one at a time beside another test, on a slower day of the machine.
  PeriodicSphereArray.MomentumExchangeDilutePhi0065At16CellsPerDiameter       # 347 / 87
  PeriodicSphereArray.MomentumExchangeQuadraticDilutePhi0065At16CellsPerDiameter  # (not measured) / 52 beside two runs
  LbmCurvedWalls.HalfwayBounceBackOnTheSameFlowIsFirstOrderAndLessAccurate    # 136 / 5.7
  LbmCurvedWalls.InterpolatedBounceBackConvergesAtSecondOrderOnCouetteFlow    # 77 / 2.8
  # 2026-11-28, release beside a one-thread run; the linear rule's tests' grids, so about as slow.
  LbmCurvedWalls.QuadraticInterpolationConvergesAtSecondOrder                 # (not measured) / 3.2
  LbmCurvedWalls.QuadraticInterpolationHalvesTheLinearRulesErrorAtLowTauUnderRecursiveRegularisation  # (not measured) / 9.2
  Release.HeldBodyMovesAsTheTowedOneUntilItsReleaseThenSlowsTowardsItsTerminalSpeed  # 51 / 4.0
  # Measured 2026-11-26 on a clean clone's CI run (the sanitizer stage at 940 s took the command to
  # within a minute of its budget). The kernels and couplings they run stay under the sanitizers
  # through the lighter tests: the golden and shipped-case runs (periodic_sphere_array,
  # fixed_sphere_stream with the momentum exchange), Health.DensityInsideABodyWithInteriorMarkers...,
  # RestartTest.MomentumExchange..., LbmPoiseuille.NonMagicTrt..., LbmConservation.* (every collision).
  PeriodicSphereArray.InteriorMarkersDensePhi0268At16CellsPerDiameter         # 30 / 1.9
  PeriodicSphereArray.DensePhi0268At16CellsPerDiameter                        # 22 / 2.0
  PeriodicSphereArray.MomentumExchangeDensePhi0268At16CellsPerDiameter        # 18 / 1.2
  LbmStability.RecursiveRegularizedStillDecaysAtTheRightRateAtTheSameTau      # 27 / 2.0
  LbmStability.CumulantStillDecaysAtTheRightRateAtTheSameTau                  # (not measured) / 5.1 on a loaded machine, the rr one beside it 6.4 (2026-12-07)
  LbmPoiseuille.BgkWallErrorIsSecondOrder                                     # 26 / 1.9
  PROPERTIES LABELS "unit;heavy")
set_tests_properties(
  FreeSettling.SphereReachesTheStandardDragCurveAndStaysSymmetric  # 575 / 69
  RunCli.StopsAtTheTerminalStateTheAnalysisFinds                   # 170 / 14
  RestartCli.TerminatedRunExits143WithACheckpointAndNoSummary      # 42 / 3.0
  RestartCli.RandomKillsContinueToTheUninterruptedResult           # 38 / 2.5 (2026-12-07, a loaded machine; six runs)
  AnalyzeCli.BrokenRunDirectoriesAreRefusedNamingTheCulprit        # 38 / 3.7
  AnalyzeCli.ViscousRunReachesASteadyObliqueTerminalState          # 36 / 3.9
  # The validation cases' grids hold 6-8 million cells (four times a ten Cate grid, whose five
  # steps take 15 s here); the other shipped cases run the same code on smaller grids.
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/mordant_pinton_1
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/mordant_pinton_2
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/uhlmann_dusek_A
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/uhlmann_dusek_B
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/uhlmann_dusek_C
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/fixed_sphere_stream  # 4.2 million cells: 52 / 4.9
  # The ten Cate cases (1.96 million cells each): 31, 27, 26 and 27 s under ASan; the golden tests
  # run the same cases on coarse grids in both builds.
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/tencate_E1
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/tencate_E2
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/tencate_E3
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/tencate_E4
  # The remaining shipped cases with their own grid of 0.2-1 million cells (2026-11-28, the sanitizer
  # tests beside a one-thread run: cube 14, cylinder 18, disk 16, grain 21, oblate 17, prolate 20,
  # towed sphere 11 s; 1-2 s each in release); the golden tests run each of them on a coarse grid
  # under the sanitizers.
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/cube
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/cylinder
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/disk
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/disk_zigzag  # 1.2 million cells, as disk
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/grain
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/oblate_spheroid
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/prolate_spheroid
  Cases/ShippedCase.RunsFiveStepsAtItsDefaultResolution/towed_sphere
  # The malformed-input tests again under mpirun -n 2: 60 s each in release, mostly mpirun starting
  # processes; the sanitizer build runs the same tests without it. They are labelled where they are
  # defined (tests/app/CMakeLists.txt, read by ctest after this file) and named here for the count
  # that scripts/run_sanitizer_tests.sh compares.
  MalformedInputUnderMpirun.Shard0
  MalformedInputUnderMpirun.Shard1
  PROPERTIES LABELS "case;heavy")
