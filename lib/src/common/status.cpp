// Names of the status codes (status.h), for messages and tests.
#include "gdof/status.h"

namespace gdof {

const char* to_string(StatusCode code) {
    switch (code) {
    case StatusCode::Ok: return "ok";
    case StatusCode::Failed: return "failed";
    case StatusCode::InvalidArgument: return "invalid argument";
    case StatusCode::NotFound: return "not found";
    case StatusCode::Io: return "i/o error";
    case StatusCode::Cancelled: return "cancelled";
    }
    return "unknown";
}

}  // namespace gdof
