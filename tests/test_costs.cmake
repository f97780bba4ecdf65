# The seconds each long test suite took (ctest's COST), read by ctest after every test
# executable's suites (tests/CMakeLists.txt). ctest -j starts the costliest tests first, but a
# clean clone (CI) has no Testing/Temporary/CTestCostData.txt: without these it starts them in
# the order they are listed, and a long one started late (KillRestart.Slow, DefaultExposure)
# ran alone at the end of its phase while the other core idled. Measured on 2 cores in a
# clean-clone run of scripts/test.sh (2026-12-05), each in the build scripts/test.sh runs it
# in (RenderFlags and CompressedGltfToolsSlow.Slow: estimated from their later speed-ups); only
# the order matters, so they need updating only when a suite's rank changes much.
# A name that is not a test of this build is ignored.
foreach(test_and_seconds IN ITEMS
        # The optimised build's (the load and slow-client suites are RUN_SERIAL, run alone).
        KillRestart.Slow:81 RenderFlags:76 FrameSweepQuick:55 CompressedGltfToolsSlow.Slow:50
        Replicas:43 RenderCancellationSlow.Slow:42 FrameRendererTest:26 RenderBudget.Slow:20
        ShaderSourcesGlslang:16 OcclusionReferenceTest:15 Replicas.Slow:13
        TransferPreliminarySlow.Slow:13 MaterialShadingTest:12 Cli:10 KillRestart:22
        OcclusionTest:8 RenderBudgetShare.Slow:8 HardCases.Slow:8 TransferPreparation.Slow:6
        HostileClients.Slow:5 FullDisk:5 ReferenceCommand:5 JobReplicas:21 Jobs.Slow:22
        # The sanitizer build's.
        DefaultExposure:77 Transfer:60 Specular:46 Store:43 Variants:43 ImageIo:42
        RenderBudget:39 TransferStore:30 ByteRanges:29 EnvironmentRegistryTest:24 AssetCamera:23
        HostileClients:20 RenderBackPressure:20 RenderLighting:18 Framing:17 StoredAssets:16
        UploadBudgetOverHttp:15 Endpoints:13 RenderCamera:12 StoredAssetsShared:12
        TransferBakeGround:11 ErrorsApiKey:10 Cors:10 Listening:10 RenderConcurrency:10
        TransferPreparation:9 RenderBudgetShare:8 ShadowCatcherOverHttp:8 RenderCaching:8
        RenderDeadline:8 HostileUploads:8 TransferBakeDeterminism:7 RigFromJson:6
        StoredAssetsApiKey:6 Errors:6 RenderMaterials:5 Jobs:6
        # Estimated, three times the optimised build's 5 s.
        HotspotsPlacement:15
        # Measured in the sanitizer build at -j2 on a machine loaded by other builds (load 6 to
        # 11), so likely high.
        JobsRetention:33 JobsListing:14)
    string(REPLACE ":" ";" test_and_seconds "${test_and_seconds}")
    list(GET test_and_seconds 0 test)
    list(GET test_and_seconds 1 seconds)
    set_tests_properties("${test}" PROPERTIES COST "${seconds}")
endforeach()
