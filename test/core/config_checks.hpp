#pragma once
// A controller configuration that `mutate` makes invalid is rejected by validate() and by the batch
// constructor, and the message names `field`.
#include <gtest/gtest.h>

#include <string>

#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {

template <typename Batch, typename Config, typename Mutate>
void expectRejected(Mutate mutate, const std::string& field) {
  Config c;
  mutate(c);
  EXPECT_THROW(Batch(c, 0, 0, 1), ParameterError) << field;
  try {
    c.validate();
    ADD_FAILURE() << "no exception for " << field;
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

}  // namespace swarm_forage
