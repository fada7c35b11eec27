// The population section of `kessler show` (show_population.cpp).
#pragma once

#include <cstdint>

#include "client/remote/remote_client.hpp"

namespace kessler::cli {

// Prints the key numbers of the run's first and newest snapshots; nothing when it has none.
void print_population(RemoteClient& client, std::int64_t run_id);

}  // namespace kessler::cli
