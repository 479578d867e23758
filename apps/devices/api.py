"""Device profiles (global, read by every authenticated caller, written by staff) and the UMA advisor."""

from drf_spectacular.utils import extend_schema
from rest_framework import permissions, viewsets
from rest_framework.decorators import action
from rest_framework.response import Response

from apps.tenancy.bounds import SafeFormParser, SafeMultiPartParser
from apps.tenancy.models import FleetToken
from continuum.engine.core.errors import InputError
from continuum.engine.device.ros_transport import ros_transport_advice
from continuum.engine.device.uma_advisor import advise, extract_thresholds

from .models import DeviceProfile
from .serializers import AdviceRequestSerializer, DeviceProfileSerializer, ThresholdsRequestSerializer


class ReadOrStaff(permissions.BasePermission):
    """Anyone authenticated reads and asks for advice; only staff users (not fleet tokens) change profiles."""

    ASKING = ("advise", "thresholds")

    def has_permission(self, request, view) -> bool:
        if not (request.user and request.user.is_authenticated):
            return False
        if request.method in permissions.SAFE_METHODS or getattr(view, "action", None) in self.ASKING:
            return True
        return request.user.is_staff and not isinstance(request.auth, FleetToken)


def advice(device: DeviceProfile, request: AdviceRequestSerializer) -> dict:
    """The communication-model recommendation (Fig. 3.7, Eqs. 3.8-3.11) and the ROS transport (3.1.3)."""
    data = request.validated_data
    answer = advise(device.to_engine(), request.profile())
    ros = ros_transport_advice(
        data["cpu_workers"],
        data["gpu_workers"],
        cuda_model=answer["recommendation"],
        off_board=data["off_board"],
        single_process=data["single_process"],
        board=device.ros_board or None,
    )
    return {"device": device.slug, "advice": answer, "ros_transport": ros}


class DeviceProfileViewSet(viewsets.ModelViewSet):
    #: Actions taking a document or a file: bodies up to limits.upload_bytes (other actions: body_bytes).
    document_actions = frozenset({"thresholds"})
    queryset = DeviceProfile.objects.all()
    serializer_class = DeviceProfileSerializer
    permission_classes = [ReadOrStaff]
    lookup_field = "slug"
    search_fields = ["name", "slug"]
    ordering_fields = ["name"]
    filterset_fields = ["io_coherent"]

    @extend_schema(request=AdviceRequestSerializer, responses={200: dict})
    @action(detail=True, methods=["post"])
    def advise(self, request, slug=None):
        """Recommend standard copy, unified memory or zero copy for an application profiled on this board,
        with the predicted speedup (Eqs. 3.10-3.11) and the ROS transport to use (ROS-SC / ROS-SHM-ZC...)."""
        device = self.get_object()
        serializer = AdviceRequestSerializer(data=request.data, context={"device": device, "request": request})
        serializer.is_valid(raise_exception=True)
        return Response(advice(device, serializer))

    @extend_schema(request={"multipart/form-data": ThresholdsRequestSerializer}, responses={200: dict})
    @action(detail=True, methods=["post"], parser_classes=[SafeMultiPartParser, SafeFormParser])
    def thresholds(self, request, slug=None):
        """GPU cache thresholds extracted from a micro-benchmark CSV (spec 01 section 9.6); the profile is not
        changed (administrators apply them in the admin)."""
        device = self.get_object()
        serializer = ThresholdsRequestSerializer(data=request.data)
        serializer.is_valid(raise_exception=True)
        upload = serializer.validated_data["file"]
        try:
            text = upload.read().decode("utf-8")
        except UnicodeDecodeError:
            raise InputError(f"{upload.name}: the file is not UTF-8 text", "file") from None
        peak = serializer.validated_data.get("peak_gbps") or device.peak_sc_gbps
        try:
            found = extract_thresholds(text, peak_gbps=peak)
        except InputError as exc:
            raise InputError(f"{upload.name}: {exc}", "file") from exc
        return Response({"device": device.slug, **found})
