// OpenSubdiv reference refinement in double precision (OpenSubdiv 3.5, Far API).
//
// Reads a mesh description on stdin, writes refined levels and limit positions on stdout, in the
// format documented in README.md. Build and run through make_refs.py:
//   g++ -O2 -o osd_ref osd_ref.cpp -losdCPU
//
// Input:
//   scheme catmark|loop
//   levels L
//   limit_level K          (apply PrimvarRefiner::Limit to the vertices of level K, 0 = none)
//   v x y z                (one line per vertex)
//   f n i0 i1 ...          (one line per face, counter-clockwise)
//   crease a b             (infinitely sharp edge)
//   corner v               (infinitely sharp vertex)
//   end
// Options: VTX_BOUNDARY_EDGE_ONLY (Blender's default), crease method uniform, triangle
// subdivision catmark — OpenSubdiv's defaults.
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <cstdio>
#include <iostream>
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

int main() {
    std::string line, scheme = "catmark";
    int levels = 1, limitLevel = 0;
    std::vector<Vertex> verts;
    std::vector<int> counts, indices, creasePairs, corners;
    while (std::getline(std::cin, line)) {
        std::istringstream in(line);
        std::string key;
        in >> key;
        if (key == "scheme") in >> scheme;
        else if (key == "levels") in >> levels;
        else if (key == "limit_level") in >> limitLevel;
        else if (key == "v") { Vertex v; in >> v.p[0] >> v.p[1] >> v.p[2]; verts.push_back(v); }
        else if (key == "f") { int n; in >> n; counts.push_back(n); for (int i = 0; i < n; ++i) { int x; in >> x; indices.push_back(x); } }
        else if (key == "crease") { int a, b; in >> a >> b; creasePairs.push_back(a); creasePairs.push_back(b); }
        else if (key == "corner") { int c; in >> c; corners.push_back(c); }
        else if (key == "end") break;
    }
    Sdc::SchemeType type = scheme == "loop" ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;
    Sdc::Options options;
    options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);

    Far::TopologyDescriptor desc;
    desc.numVertices = (int)verts.size();
    desc.numFaces = (int)counts.size();
    desc.numVertsPerFace = counts.data();
    desc.vertIndicesPerFace = indices.data();
    std::vector<float> creaseW(creasePairs.size() / 2, Sdc::Crease::SHARPNESS_INFINITE);
    std::vector<float> cornerW(corners.size(), Sdc::Crease::SHARPNESS_INFINITE);
    desc.numCreases = (int)creaseW.size();
    desc.creaseVertexIndexPairs = creasePairs.data();
    desc.creaseWeights = creaseW.data();
    desc.numCorners = (int)cornerW.size();
    desc.cornerVertexIndices = corners.data();
    desc.cornerWeights = cornerW.data();

    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    Far::TopologyRefiner* refiner = Factory::Create(desc, Factory::Options(type, options));
    Far::TopologyRefiner::UniformOptions uo(levels);
    uo.fullTopologyInLastLevel = true;
    refiner->RefineUniform(uo);

    std::vector<std::vector<Vertex> > lv(levels + 1);
    lv[0] = verts;
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    for (int l = 1; l <= levels; ++l) {
        lv[l].resize(refiner->GetLevel(l).GetNumVertices());
        primvar.Interpolate(l, lv[l - 1], lv[l]);
    }
    for (int l = 1; l <= levels; ++l) {
        Far::TopologyLevel const& tl = refiner->GetLevel(l);
        printf("level %d %d %d\n", l, tl.GetNumVertices(), tl.GetNumFaces());
        for (auto const& v : lv[l]) printf("p %.17g %.17g %.17g\n", v.p[0], v.p[1], v.p[2]);
    }
    if (limitLevel > 0 && limitLevel <= levels) {
        // Limit() reads the last level, so refine a second refiner to limitLevel only.
        Far::TopologyRefiner* r2 = Factory::Create(desc, Factory::Options(type, options));
        Far::TopologyRefiner::UniformOptions uo2(limitLevel);
        uo2.fullTopologyInLastLevel = true;  // Limit() needs the last level's vertex-edge relations
        r2->RefineUniform(uo2);
        std::vector<std::vector<Vertex> > l2(limitLevel + 1);
        l2[0] = verts;
        Far::PrimvarRefinerReal<double> pv2(*r2);
        for (int l = 1; l <= limitLevel; ++l) {
            l2[l].resize(r2->GetLevel(l).GetNumVertices());
            pv2.Interpolate(l, l2[l - 1], l2[l]);
        }
        std::vector<Vertex> lim(l2[limitLevel].size()), t1(lim.size()), t2(lim.size());
        pv2.Limit(l2[limitLevel], lim, t1, t2);
        printf("limit %d %zu\n", limitLevel, lim.size());
        for (size_t i = 0; i < lim.size(); ++i) {
            // The limit normal t1 x t2, unnormalised (direction only is compared).
            double n[3] = {t1[i].p[1] * t2[i].p[2] - t1[i].p[2] * t2[i].p[1],
                           t1[i].p[2] * t2[i].p[0] - t1[i].p[0] * t2[i].p[2],
                           t1[i].p[0] * t2[i].p[1] - t1[i].p[1] * t2[i].p[0]};
            printf("p %.17g %.17g %.17g n %.17g %.17g %.17g\n", lim[i].p[0], lim[i].p[1], lim[i].p[2], n[0], n[1], n[2]);
        }
        delete r2;
    }
    delete refiner;
    return 0;
}
