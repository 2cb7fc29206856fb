// The nodes of a PSF field (psf_field.h): one class per kind, evaluated per
// point and aperture sample. Internal to the psf_field capability.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "gdof/psf_field.h"

namespace gdof::psf {

class Node {
public:
    virtual ~Node() = default;
    virtual PsfDisplacement displace(const PsfPoint& p, double u, double v, const Roi& frame) const = 0;
    virtual bool moves_depth() const { return false; }
    virtual std::string describe() const = 0;
    // Blends append their weight fields in tree order (their index is the
    // number appended before them).
    virtual void collect_weights(std::vector<const BlurField*>& out) const { (void)out; }
};
using NodePtr = std::shared_ptr<const Node>;

NodePtr make_defocus(double scale);
NodePtr make_swirl(double strength, double power);
NodePtr make_depth(double offset, double distance);
// M(x) (u, -v) * scale, M from `channels` (1, 2 or 4 indices) of the map at
// the point: s I, diag(sx, sy) or [[m0, m1], [m2, m3]], in pixels per unit
// aperture; the map's display window stretched over the frame.
NodePtr make_image_map(std::shared_ptr<const Image> map, std::vector<int> channels, double scale, std::string name);
NodePtr make_sum(std::vector<NodePtr> children);
// `weight_index`: this blend's slot in PsfPoint::weights.
NodePtr make_blend(NodePtr a, NodePtr b, BlurField weight, int weight_index);

}  // namespace gdof::psf
