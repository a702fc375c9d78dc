// What the opaque C handles hold. Internal: for the API implementation and for
// in-tree tools (benchmarks, tests) that need the C++ objects behind a handle.
#pragma once
#include <memory>
#include <string>
#include "render/session.h"

struct rdv_scene {
  std::shared_ptr<rdv::Scene> scene;
  std::string text;  // backing store for strings handed out (messages, summary)
};

struct rdv_session {
  std::unique_ptr<rdv::Session> session;
  std::string text;  // backing store for rdv_session_stats
};
