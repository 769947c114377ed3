// OpenImageIO's TextureSystem on `wrinkle bench-texture`'s workload: a SIZE^2 RGBA8 sRGB texture of random
// texels, made into a tiled MIP-mapped file by make_texture (timed: the pyramid build), then lookups at random
// (s, t) with footprints log-uniform between 1/4096 and 1/64 of the texture, at random angles, isotropic or 8:1
// anisotropic, periodic wrap, on one thread: trilinear (MipModeTrilinear) on the isotropic footprints and
// anisotropic (MipModeAniso) on the 8:1 ones, by the one-point call and by the 16-wide batch call. Prints
// key=value lines like bench-texture's; rates are medians of ROUNDS runs after a warm-up.
// Usage: oiio_lookup DIR [SIZE] [LOOKUPS] [ROUNDS]   (DIR holds the made texture)
#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <OpenImageIO/texture.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

using namespace OIIO;
using Clock = std::chrono::steady_clock;

struct Rng {
    uint64_t s;
    float next() {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        return float(s >> 40) / float(1ull << 24);
    }
};

struct Lookups {
    std::vector<float> s, t, dsdx, dtdx, dsdy, dtdy;
};

static Lookups make_lookups(size_t n, float ratio, uint64_t seed) {
    Rng rng{seed};
    Lookups l;
    for (size_t i = 0; i < n; i++) {
        float s = rng.next(), t = rng.next();
        float w = std::pow(2.0f, -12.0f + 6.0f * rng.next());
        float a = rng.next() * 6.2831853f, c = std::cos(a), sn = std::sin(a);
        l.s.push_back(s);
        l.t.push_back(t);
        l.dsdx.push_back(ratio * w * c);
        l.dtdx.push_back(ratio * w * sn);
        l.dsdy.push_back(-w * sn);
        l.dtdy.push_back(w * c);
    }
    return l;
}

static double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

int main(int argc, char** argv) {
    std::string dir = argc > 1 ? argv[1] : ".";
    int size = argc > 2 ? std::atoi(argv[2]) : 4096;
    size_t n = argc > 3 ? std::atol(argv[3]) : 1000000;
    int rounds = argc > 4 ? std::atoi(argv[4]) : 3;
    OIIO::attribute("threads", 1);

    ImageSpec spec(size, size, 4, TypeDesc::UINT8);
    spec.attribute("oiio:ColorSpace", "sRGB");
    ImageBuf src(spec);
    Rng rng{7};
    std::vector<uint8_t> texels(size_t(size) * size * 4);
    for (auto& b : texels) b = uint8_t(rng.next() * 255.0f);
    src.set_pixels(ROI(0, size, 0, size, 0, 1, 0, 4), TypeDesc::UINT8, texels.data());
    std::string file = dir + "/oiio_random.tx";
    ImageSpec config;
    config.tile_width = config.tile_height = 64;
    config.attribute("maketx:filtername", "box");
    config.attribute("maketx:nthreads", 1);
    std::vector<double> builds;
    for (int r = 0; r < rounds; r++) {
        auto t0 = Clock::now();
        if (!ImageBufAlgo::make_texture(ImageBufAlgo::MakeTxTexture, src, file, config)) {
            std::fprintf(stderr, "make_texture: %s\n", OIIO::geterror().c_str());
            return 1;
        }
        builds.push_back(std::chrono::duration<double, std::milli>(Clock::now() - t0).count());
    }
    std::printf("oiio make_texture size=%dx%d threads=1 build_ms=%.1f\n", size, size, median(builds));

    TextureSystem* ts = TextureSystem::create(false);
    ts->attribute("max_memory_MB", 2048.0f);
    TextureSystem::Perthread* thread = ts->get_perthread_info();
    TextureSystem::TextureHandle* handle = ts->get_texture_handle(ustring(file));
    struct Case { const char* filter; const char* footprint; Tex::MipMode mode; float ratio; };
    for (Case c : {Case{"trilinear", "iso", Tex::MipMode::Trilinear, 1.0f},
                   Case{"aniso", "aniso8", Tex::MipMode::Aniso, 8.0f}}) {
        Lookups l = make_lookups(n, c.ratio, 0x9E3779B97F4A7C15ull ^ uint64_t(c.ratio));
        TextureOpt opt;
        opt.mipmode = TextureOpt::MipMode(int(c.mode));
        opt.interpmode = TextureOpt::InterpBilinear;
        opt.swrap = opt.twrap = TextureOpt::WrapPeriodic;
        TextureOptBatch bopt;
        // TextureOptBatch leaves its per-lane arrays uninitialised (only rnd is set): widths of zero shrink
        // every footprint to a point, which made the batch call a bilinear lookup of level 0 instead of the
        // filter asked for. They are given TextureOpt's defaults.
        for (int i = 0; i < Tex::BatchWidth; i++) {
            bopt.sblur[i] = bopt.tblur[i] = bopt.rblur[i] = 0.0f;
            bopt.swidth[i] = bopt.twidth[i] = bopt.rwidth[i] = 1.0f;
        }
        bopt.mipmode = c.mode;
        bopt.interpmode = Tex::InterpMode::Bilinear;
        bopt.swrap = bopt.twrap = Tex::Wrap::Periodic;
        std::vector<float> out(16 * 4);
        double sink = 0;
        auto point = [&]() {
            for (size_t i = 0; i < n; i++) {
                ts->texture(handle, thread, opt, l.s[i], l.t[i], l.dsdx[i], l.dtdx[i], l.dsdy[i], l.dtdy[i], 4,
                            out.data());
                sink += out[0];
            }
        };
        auto batch = [&]() {
            for (size_t i = 0; i + Tex::BatchWidth <= n; i += Tex::BatchWidth) {
                ts->texture(handle, thread, bopt, Tex::RunMaskOn, &l.s[i], &l.t[i], &l.dsdx[i], &l.dtdx[i],
                            &l.dsdy[i], &l.dtdy[i], 4, out.data());
                sink += out[0];
            }
        };
        // The two calls must filter alike: the first lookups' colours by both, compared.
        float worst = 0.0f;
        std::vector<float> one(4);
        for (size_t i = 0; i < 64 * size_t(Tex::BatchWidth); i += Tex::BatchWidth) {
            ts->texture(handle, thread, bopt, Tex::RunMaskOn, &l.s[i], &l.t[i], &l.dsdx[i], &l.dtdx[i], &l.dsdy[i],
                        &l.dtdy[i], 4, out.data());
            for (int lane = 0; lane < Tex::BatchWidth; lane++) {
                ts->texture(handle, thread, opt, l.s[i + lane], l.t[i + lane], l.dsdx[i + lane], l.dtdx[i + lane],
                            l.dsdy[i + lane], l.dtdy[i + lane], 4, one.data());
                for (int ch = 0; ch < 4; ch++)
                    worst = std::max(worst, std::abs(one[ch] - out[ch * Tex::BatchWidth + lane]));
            }
        }
        if (worst > 1e-5f) {
            std::fprintf(stderr, "oiio: the batch call filters otherwise than the point call (%s, differs by %g)\n",
                         c.filter, worst);
            return 1;
        }
        double rates[2];
        int k = 0;
        for (int which = 0; which < 2; which++) {
            std::vector<double> r;
            for (int round = 0; round <= rounds; round++) {
                auto t0 = Clock::now();
                which == 0 ? point() : batch();
                double s = std::chrono::duration<double>(Clock::now() - t0).count();
                if (round > 0) r.push_back(n / s / 1e6);
            }
            rates[k++] = median(r);
        }
        std::printf("oiio filter=%s footprint=%s order=random mlookups_per_s_1thread=%.2f batch%d_1thread=%.2f sink=%.1f\n",
                    c.filter, c.footprint, rates[0], Tex::BatchWidth, rates[1], sink);
    }
    TextureSystem::destroy(ts);
    return 0;
}
