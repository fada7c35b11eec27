// The values of every scenario field left unset (the scenario reference in the README lists the same):
// the paper's, except the step (30 s, with the Blanes-Moan integrator; the paper's 10 s with Yoshida's
// is deploy/scenarios/paper.yaml).
#pragma once

#include <array>
#include <string_view>

namespace kessler::scenario_defaults {

inline constexpr std::string_view kStartEpoch = "2022-01-01T00:00:00Z";
inline constexpr double kDurationDays = 1.0;
inline constexpr double kDtS = 30.0;  // with the default integrator, blanes_moan4
inline constexpr double kBurnUpAltitudeKm = 150.0;
inline constexpr double kKappaMax = 10.0;
inline constexpr double kActivePassiveMaxPassiveRadiusM = 0.10;
// NRLMSISE-00's constant solar activity: a moderate Sun.
inline constexpr double kConstantF107Sfu = 150.0;
inline constexpr double kConstantAp = 15.0;
inline constexpr int kCheckpointsPerRun = 50;  // every_steps default: total steps / 50
inline constexpr double kCheckpointEveryWallS = 60.0;
inline constexpr unsigned long long kSeed = 1;
// Ingest (the paper's dataset section).
inline constexpr double kMinPerigeeKm = 175.0;
inline constexpr double kMaxApogeeKm = 2000.0;
inline constexpr double kMaxEpochAfterStartDays = 30.0;
inline constexpr std::array<std::string_view, 3> kExcludeNames = {"ISS (*)", "STARLINK*", "ONEWEB*"};
inline constexpr double kSyntheticActiveFraction = 0.125;
inline constexpr double kSyntheticMinAltitudeKm = 300.0;
inline constexpr double kSyntheticMaxAltitudeKm = 1500.0;
// Breakups (off by default; the core's BreakupSettings holds the same values).
inline constexpr double kBreakupSeparationS = 600.0;
inline constexpr double kBreakupMinCharacteristicLengthM = 0.10;
inline constexpr double kBreakupMaxCharacteristicLengthM = 1.0;  // the model's Lc_min range is (0, 1] m
inline constexpr double kBreakupExplosionScale = 1.0;
inline constexpr unsigned long long kBreakupMaxFragmentsPerEvent = 1'000'000;

// Traffic (off by default; the core's DisposalSettings holds the same values).
inline constexpr double kTrafficWindowYears = 8.0;  // business as usual: the IADC's 8-year window
inline constexpr double kDisposalSuccessProbability = 0.9;
inline constexpr double kDisposalTargetLifetimeYears = 25.0;
inline constexpr unsigned long long kTrafficMaxPlannedObjects = 10'000'000;  // in the inline plan

inline constexpr std::array<std::string_view, 3> kDatasets = {"catalog-2022", "catalog-2019", "leo-19647"};
inline constexpr std::array<std::string_view, 4> kObjectTypes = {"PAYLOAD", "ROCKET BODY", "DEBRIS",
                                                                 "UNKNOWN"};

}  // namespace kessler::scenario_defaults
