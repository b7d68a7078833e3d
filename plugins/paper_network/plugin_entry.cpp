// Entry point of the paper_network plugin.
#include "core/plugin/plugin_api.h"
#include "plugins/paper_network/paper_network.h"

FACETOOL_DEFINE_PLUGIN(facetool::paper_network::PaperNetwork, FACETOOL_PLUGIN_NETWORK,
                       "paper_network", "1.0.0",
                       "Zhong et al.'s network: albedo, normal, SH visibility and SH light from a "
                       "face crop")
