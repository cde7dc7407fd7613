#include "render/scene.h"
