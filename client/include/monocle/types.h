// monocle's values (Pose, CameraStatus, Calibration, ...), as the client library returns them.
// They are the wire's values, defined once in idl/protocol/values.h; that file is installed
// under this name, so an installed client sees the definitions here.
#pragma once

#include "idl/protocol/values.h"
