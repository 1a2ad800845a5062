// OpenSubdiv 3.5 (Far API, double precision) on one OBJ shape with OpenSubdiv's `t` tags.
//
// Usage: osd_shape catmark|loop LEVELS < shape.obj
// Build: g++ -O1 -o osd_shape osd_shape.cpp -losdCPU
//
// Reads `v x y z`, `f i j k ...` (1-based) and the tags of OpenSubdiv's regression shapes
// (0-based vertex ids): `t crease N/M/0 v0 v1 ... s...` (a chain of N vertices, one sharpness or
// one per edge), `t corner N/M/0 v... s...`, `t interpolateboundary 1/0/0 m` (0 none, 1 edge and
// corner, 2 edge only; edge only when absent), `t creasemethod 0/0/1 normal|chaikin`,
// `t smoothtriangles 0/0/1 catmark|smooth`.
//
// Writes, for every level L in 1..=LEVELS, `level L V F` then V lines `p x y z` and F lines
// `f i j k ...` (0-based, that level's own numbering); then `limit LEVELS V` and V lines
// `p x y z r` with PrimvarRefiner::Limit of the last level's vertices and the vertex rule there
// (1 smooth, 2 dart, 4 crease, 8 corner).
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <cstdio>
#include <cstdlib>
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

static void fail(std::string const& why) {
    fprintf(stderr, "osd_shape: %s\n", why.c_str());
    exit(2);
}

int main(int argc, char** argv) {
    if (argc != 3) fail("usage: osd_shape catmark|loop LEVELS < shape.obj");
    std::string scheme = argv[1];
    int levels = atoi(argv[2]);
    if (levels < 1 || levels > 8) fail("LEVELS must be 1..8");
    Sdc::Options options;
    options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
    options.SetCreasingMethod(Sdc::Options::CREASE_UNIFORM);
    options.SetTriangleSubdivision(Sdc::Options::TRI_SUB_CATMARK);

    std::vector<Vertex> verts;
    std::vector<int> counts, indices, creasePairs, corners;
    std::vector<float> creaseW, cornerW;
    std::string line;
    while (std::getline(std::cin, line)) {
        std::istringstream in(line);
        std::string key;
        in >> key;
        if (key == "v") {
            Vertex v;
            in >> v.p[0] >> v.p[1] >> v.p[2];
            verts.push_back(v);
        } else if (key == "f") {
            int n = 0, x;
            while (in >> x) {
                indices.push_back(x - 1);
                ++n;
            }
            counts.push_back(n);
        } else if (key == "t") {
            std::string name, shape;
            in >> name >> shape;
            int ni = 0, nf = 0, ns = 0;
            if (sscanf(shape.c_str(), "%d/%d/%d", &ni, &nf, &ns) < 2) fail("bad tag: " + line);
            std::vector<int> ints(ni);
            std::vector<float> floats(nf);
            std::vector<std::string> strings(ns);
            for (int& i : ints) in >> i;
            for (float& f : floats) in >> f;
            for (std::string& s : strings) in >> s;
            if (!in && !in.eof()) fail("bad tag: " + line);
            if (name == "crease") {
                for (int k = 0; k + 1 < ni; ++k) {
                    creasePairs.push_back(ints[k]);
                    creasePairs.push_back(ints[k + 1]);
                    creaseW.push_back(nf == 1 ? floats[0] : floats[k]);
                }
            } else if (name == "corner") {
                for (int k = 0; k < ni; ++k) {
                    corners.push_back(ints[k]);
                    cornerW.push_back(nf == 1 ? floats[0] : floats[k]);
                }
            } else if (name == "interpolateboundary") {
                Sdc::Options::VtxBoundaryInterpolation m[3] = {Sdc::Options::VTX_BOUNDARY_NONE,
                                                               Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER,
                                                               Sdc::Options::VTX_BOUNDARY_EDGE_ONLY};
                if (ni != 1 || ints[0] < 0 || ints[0] > 2) fail("bad interpolateboundary: " + line);
                options.SetVtxBoundaryInterpolation(m[ints[0]]);
            } else if (name == "creasemethod") {
                options.SetCreasingMethod(strings.at(0) == "chaikin" ? Sdc::Options::CREASE_CHAIKIN
                                                                     : Sdc::Options::CREASE_UNIFORM);
            } else if (name == "smoothtriangles") {
                options.SetTriangleSubdivision(strings.at(0) == "smooth" ? Sdc::Options::TRI_SUB_SMOOTH
                                                                         : Sdc::Options::TRI_SUB_CATMARK);
            }
        }
    }
    Sdc::SchemeType type = scheme == "loop" ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK;

    Far::TopologyDescriptor desc;
    desc.numVertices = (int)verts.size();
    desc.numFaces = (int)counts.size();
    desc.numVertsPerFace = counts.data();
    desc.vertIndicesPerFace = indices.data();
    desc.numCreases = (int)creaseW.size();
    desc.creaseVertexIndexPairs = creasePairs.data();
    desc.creaseWeights = creaseW.data();
    desc.numCorners = (int)cornerW.size();
    desc.cornerVertexIndices = corners.data();
    desc.cornerWeights = cornerW.data();

    typedef Far::TopologyRefinerFactory<Far::TopologyDescriptor> Factory;
    Far::TopologyRefiner* refiner = Factory::Create(desc, Factory::Options(type, options));
    if (!refiner) fail("OpenSubdiv refused the topology");
    Far::TopologyRefiner::UniformOptions uo(levels);
    uo.fullTopologyInLastLevel = true;  // Limit() needs the last level's vertex-edge relations
    refiner->RefineUniform(uo);

    std::vector<std::vector<Vertex> > lv(levels + 1);
    lv[0] = verts;
    Far::PrimvarRefinerReal<double> primvar(*refiner);
    for (int l = 1; l <= levels; ++l) {
        Far::TopologyLevel const& tl = refiner->GetLevel(l);
        lv[l].resize(tl.GetNumVertices());
        primvar.Interpolate(l, lv[l - 1], lv[l]);
        printf("level %d %d %d\n", l, tl.GetNumVertices(), tl.GetNumFaces());
        for (auto const& v : lv[l]) printf("p %.17g %.17g %.17g\n", v.p[0], v.p[1], v.p[2]);
        for (int f = 0; f < tl.GetNumFaces(); ++f) {
            Far::ConstIndexArray fv = tl.GetFaceVertices(f);
            printf("f");
            for (int k = 0; k < fv.size(); ++k) printf(" %d", fv[k]);
            printf("\n");
        }
    }
    Far::TopologyLevel const& last = refiner->GetLevel(levels);
    std::vector<Vertex> lim(lv[levels].size());
    primvar.Limit(lv[levels], lim);
    printf("limit %d %zu\n", levels, lim.size());
    for (size_t i = 0; i < lim.size(); ++i) {
        printf("p %.17g %.17g %.17g %d\n", lim[i].p[0], lim[i].p[1], lim[i].p[2], (int)last.GetVertexRule((int)i));
    }
    delete refiner;
    return 0;
}
