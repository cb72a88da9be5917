// cpp-gradient: a keylo detector plugin in C++.
//
// Grid-bucketed gradient maxima: each `cell` x `cell` bucket keeps its pixel of largest Sobel
// gradient magnitude when it is at least `threshold`. Exceptions are caught inside every
// function and reported as KEYLO_ERR_PANIC: none may cross the C boundary.
//
// Build:  c++ -std=c++17 -shared -fPIC -O2 -I crates/keylo-plugin/include
//             plugins/cpp-gradient/gradient.cpp -o libcpp-gradient.so
// Use:    [detector] kind = "plugin:cpp-gradient"  cell = 16  threshold = 40.0
#include <cmath>
#include <cstdio>
#include <exception>
#include <sstream>
#include <string>
#include <vector>

#include "keylo_plugin.h"

namespace {

struct Gradient {
    int cell = 16;
    float threshold = 40.0f;
    std::vector<KeyloKeypoint> keypoints;
};

int32_t fail(KeyloError *err, int32_t code, const std::string &message) {
    if (err) {
        err->code = code;
        std::snprintf(err->message, KEYLO_ERROR_MESSAGE_LEN, "%s", message.c_str());
    }
    return code;
}

template <typename F>
int32_t guarded(KeyloError *err, F &&f) {
    try {
        return f();
    } catch (const std::exception &e) {
        return fail(err, KEYLO_ERR_PANIC, std::string("exception: ") + e.what());
    } catch (...) {
        return fail(err, KEYLO_ERR_PANIC, "unknown exception");
    }
}

void *create(KeyloError *err) {
    void *state = nullptr;
    guarded(err, [&] {
        state = new Gradient();
        return KEYLO_OK;
    });
    return state;
}

int32_t configure(void *state, const char *toml, KeyloError *err) {
    return guarded(err, [&] {
        auto *g = static_cast<Gradient *>(state);
        std::istringstream lines(toml ? toml : "");
        std::string line;
        while (std::getline(lines, line)) {
            if (line.empty() || line[0] == '#') continue;
            auto eq = line.find('=');
            std::string key = line.substr(0, line.find_first_of(" ="));
            double value = eq == std::string::npos ? NAN : std::strtod(line.c_str() + eq + 1, nullptr);
            if (key == "cell" && value >= 3 && value <= 1024) {
                g->cell = static_cast<int>(value);
            } else if (key == "threshold" && value >= 0) {
                g->threshold = static_cast<float>(value);
            } else {
                return fail(err, KEYLO_ERR_CONFIG,
                            "`" + line + "`: expected cell = 3..1024 or threshold >= 0");
            }
        }
        return KEYLO_OK;
    });
}

void destroy(void *state) { delete static_cast<Gradient *>(state); }

int32_t detect(void *state, const KeyloImage *img, KeyloKeypoints *out, KeyloError *err) {
    return guarded(err, [&] {
        auto *g = static_cast<Gradient *>(state);
        if (img->pixel_type != KEYLO_PIXEL_U8) return fail(err, KEYLO_ERR_INPUT, "8-bit images only");
        auto px = [&](uint32_t x, uint32_t y) {
            return static_cast<float>(img->data[size_t(y) * img->stride + size_t(x) * img->channels]);
        };
        g->keypoints.clear();
        const uint32_t c = static_cast<uint32_t>(g->cell);
        for (uint32_t cy = 0; cy < img->height; cy += c) {
            for (uint32_t cx = 0; cx < img->width; cx += c) {
                float best = -1.0f;
                uint32_t bx = 0, by = 0;
                for (uint32_t y = cy ? cy : 1; y < cy + c && y + 1 < img->height; ++y) {
                    for (uint32_t x = cx ? cx : 1; x < cx + c && x + 1 < img->width; ++x) {
                        float gx = px(x + 1, y - 1) + 2 * px(x + 1, y) + px(x + 1, y + 1) -
                                   px(x - 1, y - 1) - 2 * px(x - 1, y) - px(x - 1, y + 1);
                        float gy = px(x - 1, y + 1) + 2 * px(x, y + 1) + px(x + 1, y + 1) -
                                   px(x - 1, y - 1) - 2 * px(x, y - 1) - px(x + 1, y - 1);
                        float m = std::sqrt(gx * gx + gy * gy);
                        if (m >= g->threshold && m > best) {
                            best = m;
                            bx = x;
                            by = y;
                        }
                    }
                }
                if (best >= 0.0f) {
                    g->keypoints.push_back({float(bx), float(by), 7.0f, -1.0f, best, 0, 0});
                }
            }
        }
        out->data = g->keypoints.data();
        out->len = g->keypoints.size();
        return KEYLO_OK;
    });
}

const KeyloPluginKind KINDS[] = {{
    KEYLO_STAGE_DETECTOR,
    "grid-bucketed Sobel gradient maxima (C++ example plugin)",
    create,
    configure,
    destroy,
    detect,
    nullptr,  // describe
    nullptr,  // downsample
    nullptr,  // register_cloud
    nullptr,  // set_motion_prior (ABI 3 registrar hooks: not a registrar)
    nullptr,  // set_pose
    nullptr,  // reset
    nullptr,  // local_map
}};

const KeyloPluginInfo INFO = {KEYLO_PLUGIN_ABI_VERSION, "cpp-gradient", "0.1.0", KINDS, 1};

}  // namespace

extern "C" const KeyloPluginInfo *keylo_plugin_entry(void) { return &INFO; }
