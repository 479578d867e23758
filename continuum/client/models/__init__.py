"""Contains all the data models used in inputs/outputs"""

from .admission_report_request import AdmissionReportRequest
from .advice_request_request import AdviceRequestRequest
from .algorithm_enum import AlgorithmEnum
from .allocation_request_request import AllocationRequestRequest
from .allocation_run import AllocationRun
from .allocation_run_source_enum import AllocationRunSourceEnum
from .allocations_list_source import AllocationsListSource
from .application import Application
from .application_generate_request import ApplicationGenerateRequest
from .application_import_format_enum import ApplicationImportFormatEnum
from .application_import_request import ApplicationImportRequest
from .application_import_result import ApplicationImportResult
from .application_list import ApplicationList
from .application_request import ApplicationRequest
from .arch_enum import ArchEnum
from .assertion import Assertion
from .assertion_request import AssertionRequest
from .assignment import Assignment
from .b_score_argument_enum import BScoreArgumentEnum
from .blank_enum import BlankEnum
from .build_images_request_request import BuildImagesRequestRequest
from .capacity_source_enum import CapacitySourceEnum
from .cluster import Cluster
from .cluster_document_link_request import ClusterDocumentLinkRequest
from .cluster_document_node_request import ClusterDocumentNodeRequest
from .cluster_document_node_request_labels import ClusterDocumentNodeRequestLabels
from .cluster_document_node_request_taints_item import ClusterDocumentNodeRequestTaintsItem
from .cluster_import_request import ClusterImportRequest
from .cluster_ref_request import ClusterRefRequest
from .cluster_request import ClusterRequest
from .cluster_request_request import ClusterRequestRequest
from .clustering import Clustering
from .clustering_container_bandwidth_item import ClusteringContainerBandwidthItem
from .clustering_containers_item import ClusteringContainersItem
from .clustering_dockerfiles_type_0 import ClusteringDockerfilesType0
from .clustering_list import ClusteringList
from .clusterings_dockerfiles_retrieve_archive import ClusteringsDockerfilesRetrieveArchive
from .comm_mode_enum import CommModeEnum
from .compare_request_request import CompareRequestRequest
from .comparison import Comparison
from .comparison_figures import ComparisonFigures
from .comparison_list import ComparisonList
from .comparison_relative import ComparisonRelative
from .comparison_schedules_item import ComparisonSchedulesItem
from .compute_node import ComputeNode
from .compute_node_request import ComputeNodeRequest
from .compute_node_status_enum import ComputeNodeStatusEnum
from .container_deployment import ContainerDeployment
from .container_deployment_state_enum import ContainerDeploymentStateEnum
from .criticality_enum import CriticalityEnum
from .current_model_enum import CurrentModelEnum
from .dag_class_enum import DagClassEnum
from .decision_enum import DecisionEnum
from .device_profile import DeviceProfile
from .device_profile_request import DeviceProfileRequest
from .devices_advise_create_response_200 import DevicesAdviseCreateResponse200
from .devices_thresholds_create_response_200 import DevicesThresholdsCreateResponse200
from .duplicate_enum import DuplicateEnum
from .event_batch import EventBatch
from .event_batch_request import EventBatchRequest
from .eviction_policy_enum import EvictionPolicyEnum
from .fleet import Fleet
from .generator_enum import GeneratorEnum
from .handler import Handler
from .handler_request import HandlerRequest
from .handler_sync_request import HandlerSyncRequest
from .image_options_request import ImageOptionsRequest
from .job import Job
from .job_detail import JobDetail
from .job_log_line import JobLogLine
from .job_state_enum import JobStateEnum
from .jobs_list_state import JobsListState
from .linear_resource_enum import LinearResourceEnum
from .link import Link
from .link_request import LinkRequest
from .migration_event import MigrationEvent
from .mode_enum import ModeEnum
from .monitor import Monitor
from .monitor_request import MonitorRequest
from .monitor_verdict import MonitorVerdict
from .monitoring import Monitoring
from .monitoring_report import MonitoringReport
from .monitoring_report_source_enum import MonitoringReportSourceEnum
from .monitors_list_verdict import MonitorsListVerdict
from .node_admission import NodeAdmission
from .node_taint import NodeTaint
from .node_verdict import NodeVerdict
from .node_verdict_scores import NodeVerdictScores
from .nodes_list_arch import NodesListArch
from .nodes_list_criticality import NodesListCriticality
from .nodes_list_status import NodesListStatus
from .outcome_enum import OutcomeEnum
from .paginated_allocation_run_list import PaginatedAllocationRunList
from .paginated_application_list_list import PaginatedApplicationListList
from .paginated_assertion_list import PaginatedAssertionList
from .paginated_assignment_list import PaginatedAssignmentList
from .paginated_cluster_list import PaginatedClusterList
from .paginated_clustering_list_list import PaginatedClusteringListList
from .paginated_comparison_list_list import PaginatedComparisonListList
from .paginated_compute_node_list import PaginatedComputeNodeList
from .paginated_device_profile_list import PaginatedDeviceProfileList
from .paginated_fleet_list import PaginatedFleetList
from .paginated_handler_list import PaginatedHandlerList
from .paginated_job_list import PaginatedJobList
from .paginated_link_list import PaginatedLinkList
from .paginated_migration_event_list import PaginatedMigrationEventList
from .paginated_monitor_list import PaginatedMonitorList
from .paginated_monitor_verdict_list import PaginatedMonitorVerdictList
from .paginated_monitoring_list import PaginatedMonitoringList
from .paginated_monitoring_report_list import PaginatedMonitoringReportList
from .paginated_node_admission_list import PaginatedNodeAdmissionList
from .paginated_node_taint_list import PaginatedNodeTaintList
from .paginated_placement_list_list import PaginatedPlacementListList
from .paginated_real_time_list import PaginatedRealTimeList
from .paginated_remap_event_list import PaginatedRemapEventList
from .paginated_ros_graph_list_list import PaginatedRosGraphListList
from .paginated_rt_decision_list import PaginatedRTDecisionList
from .paginated_rt_event_list import PaginatedRTEventList
from .paginated_rt_plan_list import PaginatedRTPlanList
from .paginated_rt_pod_list import PaginatedRTPodList
from .paginated_rt_policy_list import PaginatedRTPolicyList
from .paginated_schedule_list_list import PaginatedScheduleListList
from .paginated_violation_list import PaginatedViolationList
from .patched_application_request import PatchedApplicationRequest
from .patched_assertion_request import PatchedAssertionRequest
from .patched_cluster_request import PatchedClusterRequest
from .patched_compute_node_request import PatchedComputeNodeRequest
from .patched_device_profile_request import PatchedDeviceProfileRequest
from .patched_handler_request import PatchedHandlerRequest
from .patched_link_request import PatchedLinkRequest
from .patched_monitor_request import PatchedMonitorRequest
from .patched_real_time_request import PatchedRealTimeRequest
from .patched_ros_graph_request import PatchedRosGraphRequest
from .patched_ros_graph_request_levels import PatchedRosGraphRequestLevels
from .patched_ros_graph_request_nodes import PatchedRosGraphRequestNodes
from .patched_ros_graph_request_packages import PatchedRosGraphRequestPackages
from .patched_ros_graph_request_topics import PatchedRosGraphRequestTopics
from .patched_rt_policy_request import PatchedRTPolicyRequest
from .pin_enum import PinEnum
from .place_request_request import PlaceRequestRequest
from .place_request_request_overrides import PlaceRequestRequestOverrides
from .place_request_request_weights import PlaceRequestRequestWeights
from .placement import Placement
from .placement_enum import PlacementEnum
from .placement_list import PlacementList
from .placement_node_traffic_item import PlacementNodeTrafficItem
from .placement_warnings_item import PlacementWarningsItem
from .placements_why_retrieve_response_200 import PlacementsWhyRetrieveResponse200
from .policy_enum import PolicyEnum
from .rank_mode_enum import RankModeEnum
from .real_time import RealTime
from .real_time_import_request import RealTimeImportRequest
from .real_time_request import RealTimeRequest
from .real_time_utilization import RealTimeUtilization
from .realtimes_import_create_criticality import RealtimesImportCreateCriticality
from .realtimes_import_create_sync_state import RealtimesImportCreateSyncState
from .realtimes_list_criticality import RealtimesListCriticality
from .realtimes_list_sync_state import RealtimesListSyncState
from .remap_event import RemapEvent
from .remap_event_status_enum import RemapEventStatusEnum
from .remap_request_request import RemapRequestRequest
from .remaps_list_decision import RemapsListDecision
from .remaps_list_status import RemapsListStatus
from .remaps_list_trigger import RemapsListTrigger
from .report_batch_request import ReportBatchRequest
from .report_batch_request_reports_item import ReportBatchRequestReportsItem
from .ros_board_enum import RosBoardEnum
from .ros_graph import RosGraph
from .ros_graph_effective_levels import RosGraphEffectiveLevels
from .ros_graph_import_format_enum import RosGraphImportFormatEnum
from .ros_graph_import_request import RosGraphImportRequest
from .ros_graph_list import RosGraphList
from .ros_graph_request import RosGraphRequest
from .ros_graph_request_levels import RosGraphRequestLevels
from .ros_graph_request_nodes import RosGraphRequestNodes
from .ros_graph_request_packages import RosGraphRequestPackages
from .ros_graph_request_topics import RosGraphRequestTopics
from .ros_node_edit import RosNodeEdit
from .ros_node_edit_request import RosNodeEditRequest
from .rosgraphs_list_source_format import RosgraphsListSourceFormat
from .rt_decision import RTDecision
from .rt_decisions_list_outcome import RtDecisionsListOutcome
from .rt_event import RTEvent
from .rt_event_kind_enum import RTEventKindEnum
from .rt_events_list_kind import RtEventsListKind
from .rt_plan import RTPlan
from .rt_plan_kind_enum import RTPlanKindEnum
from .rt_plans_list_kind import RtPlansListKind
from .rt_pod import RTPod
from .rt_policy import RTPolicy
from .rt_policy_request import RTPolicyRequest
from .rt_reports_create_response_201 import RtReportsCreateResponse201
from .rt_reports_list_source import RtReportsListSource
from .scenario_enum import ScenarioEnum
from .schedule import Schedule
from .schedule_list import ScheduleList
from .schedule_request_request import ScheduleRequestRequest
from .schedule_request_request_params import ScheduleRequestRequestParams
from .schedules_assignments_list_placement import SchedulesAssignmentsListPlacement
from .schedules_export_retrieve_as import SchedulesExportRetrieveAs
from .simulation_request_request import SimulationRequestRequest
from .sort_tiebreak_enum import SortTiebreakEnum
from .source_format_enum import SourceFormatEnum
from .sync_state_enum import SyncStateEnum
from .thresholds_request_request import ThresholdsRequestRequest
from .topic_edit import TopicEdit
from .topic_edit_publisher_rates_hz import TopicEditPublisherRatesHz
from .topic_edit_request import TopicEditRequest
from .topic_edit_request_publisher_rates_hz import TopicEditRequestPublisherRatesHz
from .trigger_enum import TriggerEnum
from .verdict_enum import VerdictEnum
from .verdicts_list_verdict import VerdictsListVerdict
from .violation import Violation
from .wcet import Wcet
from .wcet_request import WcetRequest
from .what_if_request import WhatIfRequest
from .what_if_request_params import WhatIfRequestParams
from .why_not import WhyNot

__all__ = (
    "AdmissionReportRequest",
    "AdviceRequestRequest",
    "AlgorithmEnum",
    "AllocationRequestRequest",
    "AllocationRun",
    "AllocationRunSourceEnum",
    "AllocationsListSource",
    "Application",
    "ApplicationGenerateRequest",
    "ApplicationImportFormatEnum",
    "ApplicationImportRequest",
    "ApplicationImportResult",
    "ApplicationList",
    "ApplicationRequest",
    "ArchEnum",
    "Assertion",
    "AssertionRequest",
    "Assignment",
    "BScoreArgumentEnum",
    "BlankEnum",
    "BuildImagesRequestRequest",
    "CapacitySourceEnum",
    "Cluster",
    "ClusterDocumentLinkRequest",
    "ClusterDocumentNodeRequest",
    "ClusterDocumentNodeRequestLabels",
    "ClusterDocumentNodeRequestTaintsItem",
    "ClusterImportRequest",
    "ClusterRefRequest",
    "ClusterRequest",
    "ClusterRequestRequest",
    "Clustering",
    "ClusteringContainerBandwidthItem",
    "ClusteringContainersItem",
    "ClusteringDockerfilesType0",
    "ClusteringList",
    "ClusteringsDockerfilesRetrieveArchive",
    "CommModeEnum",
    "CompareRequestRequest",
    "Comparison",
    "ComparisonFigures",
    "ComparisonList",
    "ComparisonRelative",
    "ComparisonSchedulesItem",
    "ComputeNode",
    "ComputeNodeRequest",
    "ComputeNodeStatusEnum",
    "ContainerDeployment",
    "ContainerDeploymentStateEnum",
    "CriticalityEnum",
    "CurrentModelEnum",
    "DagClassEnum",
    "DecisionEnum",
    "DeviceProfile",
    "DeviceProfileRequest",
    "DevicesAdviseCreateResponse200",
    "DevicesThresholdsCreateResponse200",
    "DuplicateEnum",
    "EventBatch",
    "EventBatchRequest",
    "EvictionPolicyEnum",
    "Fleet",
    "GeneratorEnum",
    "Handler",
    "HandlerRequest",
    "HandlerSyncRequest",
    "ImageOptionsRequest",
    "Job",
    "JobDetail",
    "JobLogLine",
    "JobStateEnum",
    "JobsListState",
    "LinearResourceEnum",
    "Link",
    "LinkRequest",
    "MigrationEvent",
    "ModeEnum",
    "Monitor",
    "MonitorRequest",
    "MonitorVerdict",
    "Monitoring",
    "MonitoringReport",
    "MonitoringReportSourceEnum",
    "MonitorsListVerdict",
    "NodeAdmission",
    "NodeTaint",
    "NodeVerdict",
    "NodeVerdictScores",
    "NodesListArch",
    "NodesListCriticality",
    "NodesListStatus",
    "OutcomeEnum",
    "PaginatedAllocationRunList",
    "PaginatedApplicationListList",
    "PaginatedAssertionList",
    "PaginatedAssignmentList",
    "PaginatedClusterList",
    "PaginatedClusteringListList",
    "PaginatedComparisonListList",
    "PaginatedComputeNodeList",
    "PaginatedDeviceProfileList",
    "PaginatedFleetList",
    "PaginatedHandlerList",
    "PaginatedJobList",
    "PaginatedLinkList",
    "PaginatedMigrationEventList",
    "PaginatedMonitorList",
    "PaginatedMonitorVerdictList",
    "PaginatedMonitoringList",
    "PaginatedMonitoringReportList",
    "PaginatedNodeAdmissionList",
    "PaginatedNodeTaintList",
    "PaginatedPlacementListList",
    "PaginatedRTDecisionList",
    "PaginatedRTEventList",
    "PaginatedRTPlanList",
    "PaginatedRTPodList",
    "PaginatedRTPolicyList",
    "PaginatedRealTimeList",
    "PaginatedRemapEventList",
    "PaginatedRosGraphListList",
    "PaginatedScheduleListList",
    "PaginatedViolationList",
    "PatchedApplicationRequest",
    "PatchedAssertionRequest",
    "PatchedClusterRequest",
    "PatchedComputeNodeRequest",
    "PatchedDeviceProfileRequest",
    "PatchedHandlerRequest",
    "PatchedLinkRequest",
    "PatchedMonitorRequest",
    "PatchedRTPolicyRequest",
    "PatchedRealTimeRequest",
    "PatchedRosGraphRequest",
    "PatchedRosGraphRequestLevels",
    "PatchedRosGraphRequestNodes",
    "PatchedRosGraphRequestPackages",
    "PatchedRosGraphRequestTopics",
    "PinEnum",
    "PlaceRequestRequest",
    "PlaceRequestRequestOverrides",
    "PlaceRequestRequestWeights",
    "Placement",
    "PlacementEnum",
    "PlacementList",
    "PlacementNodeTrafficItem",
    "PlacementWarningsItem",
    "PlacementsWhyRetrieveResponse200",
    "PolicyEnum",
    "RTDecision",
    "RTEvent",
    "RTEventKindEnum",
    "RTPlan",
    "RTPlanKindEnum",
    "RTPod",
    "RTPolicy",
    "RTPolicyRequest",
    "RankModeEnum",
    "RealTime",
    "RealTimeImportRequest",
    "RealTimeRequest",
    "RealTimeUtilization",
    "RealtimesImportCreateCriticality",
    "RealtimesImportCreateSyncState",
    "RealtimesListCriticality",
    "RealtimesListSyncState",
    "RemapEvent",
    "RemapEventStatusEnum",
    "RemapRequestRequest",
    "RemapsListDecision",
    "RemapsListStatus",
    "RemapsListTrigger",
    "ReportBatchRequest",
    "ReportBatchRequestReportsItem",
    "RosBoardEnum",
    "RosGraph",
    "RosGraphEffectiveLevels",
    "RosGraphImportFormatEnum",
    "RosGraphImportRequest",
    "RosGraphList",
    "RosGraphRequest",
    "RosGraphRequestLevels",
    "RosGraphRequestNodes",
    "RosGraphRequestPackages",
    "RosGraphRequestTopics",
    "RosNodeEdit",
    "RosNodeEditRequest",
    "RosgraphsListSourceFormat",
    "RtDecisionsListOutcome",
    "RtEventsListKind",
    "RtPlansListKind",
    "RtReportsCreateResponse201",
    "RtReportsListSource",
    "ScenarioEnum",
    "Schedule",
    "ScheduleList",
    "ScheduleRequestRequest",
    "ScheduleRequestRequestParams",
    "SchedulesAssignmentsListPlacement",
    "SchedulesExportRetrieveAs",
    "SimulationRequestRequest",
    "SortTiebreakEnum",
    "SourceFormatEnum",
    "SyncStateEnum",
    "ThresholdsRequestRequest",
    "TopicEdit",
    "TopicEditPublisherRatesHz",
    "TopicEditRequest",
    "TopicEditRequestPublisherRatesHz",
    "TriggerEnum",
    "VerdictEnum",
    "VerdictsListVerdict",
    "Violation",
    "Wcet",
    "WcetRequest",
    "WhatIfRequest",
    "WhatIfRequestParams",
    "WhyNot",
)
