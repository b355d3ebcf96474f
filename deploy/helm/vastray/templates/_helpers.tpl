{{/* Names: RELEASE-vastray unless the release name already says vastray. */}}
{{- define "vastray.fullname" -}}
{{- if contains "vastray" .Release.Name -}}
{{- .Release.Name | trunc 50 | trimSuffix "-" -}}
{{- else -}}
{{- printf "%s-vastray" .Release.Name | trunc 50 | trimSuffix "-" -}}
{{- end -}}
{{- end -}}

{{- define "vastray.labels" -}}
app.kubernetes.io/name: vastray
app.kubernetes.io/instance: {{ .Release.Name }}
app.kubernetes.io/version: {{ .Chart.AppVersion | quote }}
app.kubernetes.io/managed-by: {{ .Release.Service }}
helm.sh/chart: {{ printf "%s-%s" .Chart.Name .Chart.Version }}
{{- end -}}

{{- define "vastray.serverSelector" -}}
app.kubernetes.io/name: vastray
app.kubernetes.io/instance: {{ .Release.Name }}
app.kubernetes.io/component: server
{{- end -}}

{{- define "vastray.image" -}}
{{- printf "%s:%s" .Values.image.repository .Values.image.tag -}}
{{- end -}}

{{- define "vastray.claimName" -}}
{{- .Values.storage.existingClaim | default (printf "%s-data" (include "vastray.fullname" .)) -}}
{{- end -}}

{{- define "vastray.tokenSecret" -}}
{{- .Values.auth.existingSecret | default (printf "%s-token" (include "vastray.fullname" .)) -}}
{{- end -}}

{{- define "vastray.databaseSecret" -}}
{{- .Values.database.existingSecret | default (printf "%s-database" (include "vastray.fullname" .)) -}}
{{- end -}}

{{- define "vastray.hasToken" -}}
{{- if or .Values.auth.existingSecret .Values.auth.token -}}true{{- end -}}
{{- end -}}

{{- define "vastray.hasDatabase" -}}
{{- if or .Values.database.existingSecret .Values.database.url -}}true{{- end -}}
{{- end -}}

{{/* --gpu-device: server.gpuDevices, else "-1" for 0 or 1 GPU, else 0,1,...,N-1. */}}
{{- define "vastray.gpuDevices" -}}
{{- if .Values.server.gpuDevices -}}
{{- .Values.server.gpuDevices -}}
{{- else if le (int .Values.gpu.count) 1 -}}
-1
{{- else -}}
{{- $devices := list -}}
{{- range $i := until (int .Values.gpu.count) -}}{{- $devices = append $devices (toString $i) -}}{{- end -}}
{{- join "," $devices -}}
{{- end -}}
{{- end -}}

{{/* Pod-level settings shared by the server and the batch Jobs; none of them calls the
Kubernetes API, so no service account token is mounted. */}}
{{- define "vastray.podCommon" -}}
automountServiceAccountToken: false
{{- with .Values.imagePullSecrets }}
imagePullSecrets:
  {{- toYaml . | nindent 2 }}
{{- end }}
{{- if .Values.gpu.runtimeClassName }}
runtimeClassName: {{ .Values.gpu.runtimeClassName }}
{{- end }}
securityContext:
  {{- toYaml .Values.podSecurityContext | nindent 2 }}
{{- end -}}

{{/* Container env: with GPUs, lavapipe is hidden from the Vulkan loader (values.yaml, gpu). */}}
{{- define "vastray.gpuEnv" -}}
{{- if gt (int .Values.gpu.count) 0 }}
- name: VK_LOADER_DRIVERS_DISABLE
  value: "lvp_icd*"
{{- end }}
{{- end -}}

{{- define "vastray.gpuResources" -}}
{{- $resources := deepCopy .resources -}}
{{- if gt (int .root.Values.gpu.count) 0 -}}
{{- $limits := $resources.limits | default dict -}}
{{- $_ := set $limits .root.Values.gpu.resourceName (int .root.Values.gpu.count) -}}
{{- $_ := set $resources "limits" $limits -}}
{{- end -}}
{{- toYaml $resources -}}
{{- end -}}

{{/* The server container's env: the database URL (and password) from Secrets, gpuEnv. */}}
{{- define "vastray.serverEnv" -}}
{{- if include "vastray.hasDatabase" . }}
- name: VASTRAY_DATABASE_URL
  valueFrom:
    secretKeyRef:
      name: {{ include "vastray.databaseSecret" . }}
      key: {{ .Values.database.secretKey }}
{{- with .Values.database.passwordSecret }}
{{- if .name }}
- name: PGPASSWORD
  valueFrom:
    secretKeyRef:
      name: {{ .name }}
      key: {{ .key }}
{{- end }}
{{- end }}
{{- end }}
{{- include "vastray.gpuEnv" . }}
{{- end -}}
