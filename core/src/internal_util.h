// Internal helpers of the core's sources: the shared mix and clock (ovpc/core/internal/).
#pragma once

#include "ovpc/core/internal/clock.h"
#include "ovpc/core/internal/hash.h"
