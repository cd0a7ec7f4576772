// Text helpers shared by the report's sections (internal to src/report).
#pragma once

#include <string>

#include "core/geometry.h"

namespace semvox::html {

// &, <, >, " and ' as entities.
std::string Escape(const std::string& s);
// Standard base64 (RFC 4648, with padding) of raw bytes.
std::string Base64(const std::string& bytes);
// "#rrggbb".
std::string Hex(const Rgb8& c);
// JSON text made safe inside a <script> element: every '<' (only inside strings in JSON) becomes \u003c, the same
// JSON value, so neither "</script" nor "<!--" can occur.
std::string ScriptSafeJson(const std::string& json);

}  // namespace semvox::html
