// The leo-19647 benchmark population (19,647 catalogued LEO objects at 2022-03-01T00:00:00 UTC,
// published with ESA's open-source "cascade" simulator): test_ic_19647.txt holds 7 numbers per object,
// one per line (x, y, z [m], vx, vy, vz [m/s], Earth-centred inertial, then the collision radius [m]);
// test_par_19647.txt one drag parameter per object, BSTAR over the Earth radius [1/m].
//
// Derived properties:
//   Cd A/m = 2 par / rho0, rho0 = 0.1570 / 6378137 kg/m^3 (the dataset's drag law
//            a = -(rho/rho0) par |v| v equals -1/2 rho (Cd A/m) |v| v);
//   mass   = (4/3) pi r^3 2698.9 kg/m^3 for r <= 1 cm, else (4/3) pi r^3 92.937 (2r)^-0.74 kg
//            (the paper's mass law, r in m);
//   SRP A/m = pi r^2 / mass.
// Ids are 1..19647 in file order; names "LEO19647-<id>".
#pragma once

#include <string>

#include "core/population/population.hpp"
#include "core/time/epoch.hpp"

namespace kessler {

// The dataset's epoch, 2022-03-01T00:00:00Z.
UtcEpoch leo19647_epoch();
inline constexpr const char* kLeo19647EpochIso = "2022-03-01T00:00:00Z";
inline constexpr std::size_t kLeo19647Objects = 19647;
inline constexpr double kLeo19647Rho0_kg_m3 = 0.1570 / 6378137.0;

// Mass [kg] of a debris sphere of radius r [m] by the paper's law.
double paper_mass_kg(double radius_m);

// Reads dir/test_ic_19647.txt and dir/test_par_19647.txt. Throws std::runtime_error naming the file and
// line on a missing file, a wrong count or a bad number, and naming the object and field when an
// object is not sound (Population::validate).
Population load_leo19647(const std::string& dir);

}  // namespace kessler
