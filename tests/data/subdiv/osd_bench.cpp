// Times OpenSubdiv's own CPU refiner on an OBJ file: uniform refinement of the topology
// (Far::TopologyRefinerFactory::Create + RefineUniform) and of positions
// (Far::PrimvarRefiner::Interpolate, double), for Catmull-Clark or Loop — the counterpart of
// kernel/benches/subdiv.rs (which times the same phases of blocksmith's Refiner, and writes the
// inputs it times as OBJ files for this program; bench_vs_osd.sh runs both and prints ratios).
// Crease tags `t crease 2/1/0 a b s` (0-based, as blocksmith writes them) are read as
// OpenSubdiv's creases; edge-only boundaries, uniform creasing.
//
//   g++ -O2 -o osd_bench osd_bench.cpp -losdCPU
//   ./osd_bench catmark mesh.obj 3 5      # scheme, mesh, levels, repetitions
//   ./osd_bench catmark mesh.obj 3 once   # one run of osd_far_once_measured, for callgrind
// Prints: OSD_BENCH scheme=... topology_med_s=... positions_med_s=... total_med_s=... F=...
// or, with `once`: OSD_ONCE scheme=... F0=... V=... F=... seconds=...
//
// The timed work is farTopology + farPositions; `once` runs both once inside
// osd_far_once_measured (never inlined), so that callgrind_vs_osd.sh can count its instructions
// alone with --toggle-collect (deleting the refiner and the buffers happens after it returns, as
// the timed loop leaves them out too).
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

using namespace OpenSubdiv;

struct Vertex {
    double p[3];
    void Clear(void* = 0) { p[0] = p[1] = p[2] = 0.0; }
    void AddWithWeight(Vertex const& s, double w) {
        p[0] += w * s.p[0];
        p[1] += w * s.p[1];
        p[2] += w * s.p[2];
    }
};

static double now() {
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

static double median(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v[v.size() / 2];
}

typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;

// Far's topology: the refiner created from the descriptor and refined uniformly `levels` deep.
__attribute__((noinline)) Far::TopologyRefiner* farTopology(Far::TopologyDescriptor const& desc, Sdc::SchemeType type,
                                                            Sdc::Options options, int levels) {
    Far::TopologyRefiner* refiner = Factory::Create(desc, Factory::Options(type, options));
    if (refiner) refiner->RefineUniform(Far::TopologyRefiner::UniformOptions(levels));
    return refiner;
}

// Far's positions: the control points copied into `a`, then interpolated level by level
// (PrimvarRefiner, double); the last level ends in `a`.
__attribute__((noinline)) void farPositions(Far::TopologyRefiner const& refiner, std::vector<Vertex> const& verts,
                                            int levels, std::vector<Vertex>& a, std::vector<Vertex>& b) {
    a = verts;
    Far::PrimvarRefinerReal<double> pv(refiner);
    for (int l = 1; l <= levels; ++l) {
        b.resize(refiner.GetLevel(l).GetNumVertices());
        pv.Interpolate(l, a, b);
        std::swap(a, b);
    }
}

// Topology + positions once: what callgrind_vs_osd.sh counts.
__attribute__((noinline)) Far::TopologyRefiner* osd_far_once_measured(Far::TopologyDescriptor const& desc,
                                                                      Sdc::SchemeType type, Sdc::Options options,
                                                                      int levels, std::vector<Vertex> const& verts,
                                                                      std::vector<Vertex>& a, std::vector<Vertex>& b) {
    Far::TopologyRefiner* refiner = farTopology(desc, type, options, levels);
    if (refiner) farPositions(*refiner, verts, levels, a, b);
    return refiner;
}

int main(int argc, char** argv) {
    if (argc < 3) { fprintf(stderr, "usage: osd_bench catmark|loop mesh.obj [levels] [reps]\n"); return 1; }
    std::string scheme = argv[1];
    int levels = argc > 3 ? atoi(argv[3]) : 3, reps = argc > 4 ? atoi(argv[4]) : 5;
    bool once = argc > 4 && std::string(argv[4]) == "once";
    if (!once && reps < 1) { fprintf(stderr, "osd_bench: repetitions must be a positive number or `once`\n"); return 1; }
    std::ifstream in(argv[2]);
    if (!in) { fprintf(stderr, "osd_bench: cannot read %s\n", argv[2]); return 1; }
    std::string line;
    std::vector<Vertex> verts;
    std::vector<int> counts, indices, creasePairs;
    std::vector<float> creaseW;
    while (std::getline(in, line)) {
        std::istringstream s(line);
        std::string k;
        s >> k;
        if (k == "v") { Vertex v; s >> v.p[0] >> v.p[1] >> v.p[2]; verts.push_back(v); }
        else if (k == "f") { int n = 0; std::string t; while (s >> t) { indices.push_back(atoi(t.c_str()) - 1); ++n; } counts.push_back(n); }
        else if (k == "t") {
            std::string name, shape;
            int a, b;
            float w;
            s >> name >> shape;
            if (name == "crease" && shape == "2/1/0" && (s >> a >> b >> w)) {
                creasePairs.push_back(a);
                creasePairs.push_back(b);
                creaseW.push_back(w);
            }
        }
    }
    Far::TopologyDescriptor desc;
    desc.numVertices = (int)verts.size();
    desc.numFaces = (int)counts.size();
    desc.numVertsPerFace = counts.data();
    desc.vertIndicesPerFace = indices.data();
    desc.numCreases = (int)creaseW.size();
    desc.creaseVertexIndexPairs = creasePairs.data();
    desc.creaseWeights = creaseW.data();
    Sdc::Options options;
    options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    Sdc::SchemeType type = scheme == "loop" ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
    if (once) {
        std::vector<Vertex> a, b;
        double t0 = now();
        Far::TopologyRefiner* refiner = osd_far_once_measured(desc, type, options, levels, verts, a, b);
        double t1 = now();
        if (!refiner) { fprintf(stderr, "osd_bench: OpenSubdiv refused the topology\n"); return 1; }
        printf("OSD_ONCE scheme=%s levels=%d F0=%zu creases=%zu V=%d F=%d seconds=%.5f\n", scheme.c_str(), levels,
               counts.size(), creaseW.size(), refiner->GetLevel(levels).GetNumVertices(),
               refiner->GetLevel(levels).GetNumFaces(), t1 - t0);
        delete refiner;
        return 0;
    }
    std::vector<double> tt, tp;
    int nf = 0;
    for (int r = 0; r < reps; ++r) {
        double t0 = now();
        Far::TopologyRefiner* refiner = farTopology(desc, type, options, levels);
        if (!refiner) { fprintf(stderr, "osd_bench: OpenSubdiv refused the topology\n"); return 1; }
        double t1 = now();
        std::vector<Vertex> a, b;
        farPositions(*refiner, verts, levels, a, b);
        double t2 = now();
        nf = refiner->GetLevel(levels).GetNumFaces();
        tt.push_back(t1 - t0);
        tp.push_back(t2 - t1);
        delete refiner;
    }
    printf("OSD_BENCH scheme=%s levels=%d F0=%zu creases=%zu F=%d topology_med_s=%.5f positions_med_s=%.5f total_med_s=%.5f reps=%d\n",
           scheme.c_str(), levels, counts.size(), creaseW.size(), nf, median(tt), median(tp), median(tt) + median(tp), reps);
    return 0;
}
